//! Tests of `crates/framedyn/src/scenes/spec.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::scenes::{example, Scene, DEFAULT_SCENE};

/// The integer fields' errors name the field and its range, in TOML and
/// JSON, for negative, boolean, fractional and beyond-64-bit values;
/// values within the type's range reach the field's own check.
#[test]
fn integer_fields_say_their_range() {
    let json = example(DEFAULT_SCENE).unwrap().to_json_string();
    let base: serde_json::Value = serde_json::from_str(&json).unwrap();
    let cases = [
        ("output", "every", "1 ..= 2^64 − 1"),
        ("output", "samples", "2 ..= 1e8"),
        ("method", "max_steps", "1 ..= 2^64 − 1"),
        ("method", "newton_max_iter", "1 ..= 1000"),
    ];
    for (table, field, range) in cases {
        let path = format!("{table}.{field}");
        for bad in ["-1", "true", "1.5", "18446744073709551616", "\"3\""] {
            let mut v = base.clone();
            if table == "output" {
                v[table].as_object_mut().unwrap().remove("every");
            }
            v[table][field] = serde_json::from_str(bad).unwrap();
            let e = Scene::from_json_str(&v.to_string()).unwrap_err().to_string();
            assert!(e.contains(&format!("`{path}`")) && e.contains(range), "{path} = {bad}: {e}");
            if bad == "18446744073709551616" {
                assert!(e.contains("beyond 64 bits"), "{e}");
            }
        }
        let toml = format!("{}\n", example(DEFAULT_SCENE).unwrap().to_toml_string().replace("every = 4\n", ""));
        let text = toml.replacen(&format!("[{table}]\n"), &format!("[{table}]\n{field} = -1\n"), 1);
        let e = Scene::from_toml_str(&text).unwrap_err().to_string();
        assert!(e.contains(&format!("`{path}`")) && e.contains(range), "{path} = -1 (TOML): {e}");
    }
    // In the type's range: parsed, then refused by the field's check.
    let mut v = base.clone();
    v["output"]["every"] = 0.into();
    let e = Scene::from_json_str(&v.to_string()).unwrap().validate().unwrap_err().to_string();
    assert!(e.contains("output.every") && e.contains("≥ 1"), "{e}");
    let mut v = base;
    v["output"]["every"] = serde_json::Value::Null;
    assert_eq!(Scene::from_json_str(&v.to_string()).unwrap().output.every, None);
}
