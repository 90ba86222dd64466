//! The library names its settings in messages as the API spells them, in
//! backquotes (`` `max_memory` ``), and never a command-line flag; the CLI
//! prints each such name as the flag that sets it.

/// Each setting name a library message may quote, with the flag that sets it.
const FLAG_OF_SETTING: &[(&str, &str)] = &[
    ("max_memory", "--max-memory"),
    ("max_elements", "--max-elements"),
    ("hemicube_resolution", "--hemicube-res"),
    ("patch_size", "--patch-size"),
    ("bounces", "--bounces"),
    ("shaped_gathers", "--shaped-gathers"),
    ("solver.tolerance", "--tolerance"),
    ("double_sided", "--double-sided"),
    ("overlaps", "--overlaps"),
    ("max_reflectance", "--max-reflectance"),
    ("refine.source_tolerance", "--source-tolerance"),
    ("refine.tolerance", "--refine-tolerance"),
    ("refine.dim_floor", "--dim-floor"),
    ("refine.near_floor", "--near-floor"),
    ("refine.initial_depth", "--initial-depth"),
    ("refine.max_depth", "--max-depth"),
    ("refine.min_element_area", "--min-element-area"),
    ("progressive.tolerance", "--unshot-tolerance"),
    ("progressive.max_shots", "--max-shots"),
    ("progressive.preview_every", "--preview-every"),
    ("light_groups", "--light-group"),
    ("tone_map", "--tonemap"),
    ("false_colour_range", "--false-colour-range"),
    ("sky", "--sky"),
    ("sun", "--sun"),
    ("regions", "--regions"),
    ("paths", "--paths"),
    ("points", "--points"),
    ("repeats", "--repeats"),
    ("patch_divisions", "--patch-divisions"),
    ("plane_tolerance", "--plane-tolerance"),
    ("normal_tolerance", "--normal-tolerance"),
];

/// The flag that sets library setting `name`, if the CLI has one.
pub fn flag_for(name: &str) -> Option<&'static str> {
    FLAG_OF_SETTING
        .iter()
        .find(|(setting, _)| *setting == name)
        .map(|(_, flag)| *flag)
}

/// `text` with every backquoted setting name that has a flag replaced by
/// the flag (`` `max_memory` `` becomes `--max-memory`); other backquoted
/// text is left as it is.
pub fn with_flags(text: impl AsRef<str>) -> String {
    let text = text.as_ref();
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(open) = rest.find('`') {
        let after = &rest[open + 1..];
        let Some(close) = after.find('`') else { break };
        out.push_str(&rest[..open]);
        match flag_for(&after[..close]) {
            Some(flag) => out.push_str(flag),
            None => out.push_str(&rest[open..open + close + 2]),
        }
        rest = &after[close + 1..];
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoted_setting_names_become_their_flags() {
        assert_eq!(
            with_flags("limit 2 GB; `max_memory` or `max_elements` raise it"),
            "limit 2 GB; --max-memory or --max-elements raise it"
        );
        assert_eq!(
            with_flags("loosen `solver.tolerance`"),
            "loosen --tolerance"
        );
    }

    #[test]
    fn other_backquoted_text_and_unpaired_quotes_are_kept() {
        assert_eq!(
            with_flags("run `radiosity view` on it"),
            "run `radiosity view` on it"
        );
        assert_eq!(with_flags("a ` alone `max_memory"), "a ` alone `max_memory");
        assert_eq!(with_flags("no quotes"), "no quotes");
    }

    #[test]
    fn every_flag_in_the_table_is_one_the_cli_parses() {
        use super::super::args::Cli;
        use clap::CommandFactory;
        let cli = Cli::command();
        let known: Vec<String> = cli
            .get_subcommands()
            .flat_map(|c| c.get_arguments())
            .filter_map(|a| a.get_long().map(|l| format!("--{l}")))
            .collect();
        for (setting, flag) in FLAG_OF_SETTING {
            assert!(
                known.iter().any(|k| k == flag),
                "{setting}: {flag} is no flag"
            );
        }
    }
}
