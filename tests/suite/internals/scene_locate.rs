//! Tests of `crates/framedyn/src/scenes/locate.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::__internals::toml_key_at;

#[test]
fn keys_of_toml_lines() {
    let text = "name = \"x\"\n[output]\nevery = 99999999999999999999\n[[events]]\nkind = \"plane\"\n[[events]]\nvalue = 1e999\n";
    let at = |needle: &str| toml_key_at(text, text.find(needle).unwrap());
    assert_eq!(at("9999").as_deref(), Some("output.every"));
    assert_eq!(at("\"plane").as_deref(), Some("events[0].kind"));
    assert_eq!(at("1e999").as_deref(), Some("events[1].value"));
    assert_eq!(at("\"x").as_deref(), Some("name"));
    assert_eq!(at("[output]"), None);
}
