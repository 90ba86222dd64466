//! Numbers read from (and written to) the untyped JSON in double precision.
//!
//! `gltf-json` stores factors, transforms and angles as `f32`; reading them from the
//! JSON text instead keeps every digit the file has, so a scene written by
//! [`write_scene`](super::write_scene) comes back with exactly the same materials,
//! cameras and transforms.

use serde_json::{Map, Number, Value};

/// The number at a JSON pointer, if there is one.
pub(super) fn number(raw: &Value, pointer: &str) -> Option<f64> {
    raw.pointer(pointer)?.as_f64()
}

/// The array of exactly `N` numbers at a JSON pointer, if there is one.
pub(super) fn numbers<const N: usize>(raw: &Value, pointer: &str) -> Option<[f64; N]> {
    let items = raw.pointer(pointer)?.as_array()?;
    if items.len() != N {
        return None;
    }
    let mut out = [0.0; N];
    for (slot, item) in out.iter_mut().zip(items) {
        *slot = item.as_f64()?;
    }
    Some(out)
}

/// Sets the value at a JSON pointer made of object keys and array indices,
/// creating objects on the way. Returns false (changing nothing further) if the
/// pointer crosses a value that is neither, or an array index that does not exist.
pub(super) fn set(raw: &mut Value, pointer: &str, value: Value) -> bool {
    let mut here = raw;
    let keys: Vec<&str> = pointer.split('/').skip(1).collect();
    let Some((last, path)) = keys.split_last() else {
        return false;
    };
    for key in path {
        here = match here {
            Value::Object(map) => map
                .entry(key.to_string())
                .or_insert_with(|| Value::Object(Map::new())),
            Value::Array(items) => match key.parse::<usize>().ok().and_then(|i| items.get_mut(i)) {
                Some(item) => item,
                None => return false,
            },
            _ => return false,
        };
    }
    match here {
        Value::Object(map) => {
            map.insert(last.to_string(), value);
            true
        }
        _ => false,
    }
}

/// A JSON array of finite numbers (non-finite values become 0, which glTF cannot
/// hold anyway).
pub(super) fn array(values: &[f64]) -> Value {
    Value::Array(values.iter().map(|v| scalar(*v)).collect())
}

/// A JSON number (0 for a non-finite value). Adding 0.0 writes -0.0 as 0.0.
pub(super) fn scalar(v: f64) -> Value {
    Value::Number(Number::from_f64(v + 0.0).unwrap_or_else(|| Number::from(0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn doubles_survive_a_text_round_trip() {
        let mut v = serde_json::json!({"materials": [{"name": "m"}]});
        let x = [0.1_f64, 1.0 / 3.0, 12.0 / 17.0];
        assert!(set(&mut v, "/materials/0/pbr/base", array(&x)));
        assert!(!set(&mut v, "/materials/3/x", scalar(1.0)));
        let text = serde_json::to_string(&v).unwrap();
        let back: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(numbers::<3>(&back, "/materials/0/pbr/base"), Some(x));
        assert_eq!(number(&back, "/materials/0/pbr/base/1"), Some(1.0 / 3.0));
        assert_eq!(numbers::<2>(&back, "/materials/0/pbr/base"), None);
    }
}
