use radiosity::refine::RefineSettings;
use radiosity::scenes::penumbra::by_name;
use radiosity::Settings;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let spec = by_name(&args[1]).unwrap();
    let scene = spec.scene().unwrap();
    let floor = scene
        .objects
        .iter()
        .position(|o| o.name == "floor")
        .unwrap() as u32;
    for cfg in args[2..].iter() {
        let mut r = RefineSettings::default();
        let mut s = Settings::default();
        for kv in cfg.split(',') {
            let (k, v) = kv.split_once('=').unwrap();
            match k {
                "tol" => r.tolerance = v.parse().unwrap(),
                "depth" => r.max_depth = v.parse().unwrap(),
                "uniform" => r.uniform_depth = Some(v.parse().unwrap()),
                "init" => r.initial_depth = v.parse().unwrap(),
                "res" => s.hemicube_resolution = v.parse().unwrap(),
                "ps" => s.patch_size = Some(v.parse().unwrap()),
                "m" => s.form_factors = v.parse().unwrap(),
                _ => panic!(),
            }
        }
        s.refine = r;
        let t = std::time::Instant::now();
        let sol = radiosity::solve(&scene, &s, &|_| {}).unwrap();
        let secs = t.elapsed().as_secs_f64();
        let (mut sum, mut area, mut on, mut n, mut mx) = (0.0, 0.0, 0.0f64, 0, 0.0f64);
        for e in sol.mesh.elements.values().filter(|e| e.is_leaf()) {
            let l = &sol.mesh.surfaces[e.surface as usize];
            if l.object != floor {
                continue;
            }
            let ex = spec.exact_element_mean(&l.polygon(&e.cell)).unwrap();
            on = on.max(ex.max_band());
            let d = (e.radiosity - ex).abs().max_band();
            sum += d * e.area;
            area += e.area;
            n += 1;
            mx = mx.max(d);
        }
        println!(
            "{cfg:30} floor_elems {n:6} hemicubes {:6} mean_err {:.5} max_err {:.4} {:.2}s",
            sol.stats.hemicube.hemicubes,
            sum / area / on,
            mx / on,
            secs
        );
    }
}
