//! JSON read strictly: a key given twice in one object (`{"x": 1, "x": 20}`)
//! is refused, where a JSON parser would silently keep one of the two.

use std::collections::HashSet;

use serde_json::Value;

/// Parses `text`, refusing an object that names a key twice.
pub(crate) fn parse(text: &str) -> Result<Value, String> {
    let value: Value = serde_json::from_str(text).map_err(|e| format!("JSON: {e}"))?;
    check_unique_keys(text)?;
    Ok(value)
}

/// Scans JSON text that parsed: each object's keys (the strings followed by a
/// colon) must differ, as written.
fn check_unique_keys(text: &str) -> Result<(), String> {
    // One entry per open object (its keys) or array (`None`).
    let mut open: Vec<Option<HashSet<&str>>> = Vec::new();
    let bytes = text.as_bytes();
    let mut at = 0;
    while at < bytes.len() {
        match bytes[at] {
            b'{' => open.push(Some(HashSet::new())),
            b'[' => open.push(None),
            b'}' | b']' => {
                open.pop();
            }
            b'"' => {
                let start = at + 1;
                at = start;
                while bytes[at] != b'"' {
                    at += if bytes[at] == b'\\' { 2 } else { 1 };
                }
                let string = &text[start..at];
                let after = text[at + 1..].trim_start();
                if let (true, Some(Some(keys))) = (after.starts_with(':'), open.last_mut()) {
                    if !keys.insert(string) {
                        return Err(format!(
                            "JSON: the key \"{string}\" is given twice in one object; give it once"
                        ));
                    }
                }
            }
            _ => {}
        }
        at += 1;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_key_twice_is_refused() {
        assert!(parse(r#"{"x": 1, "y": {"x": 2}, "z": ["x", "x"]}"#).is_ok());
        let e = parse(r#"[{"x": 1, "x": 20}]"#).unwrap_err();
        assert!(e.contains("\"x\" is given twice"), "{e}");
        assert!(parse(r#"{"a\"b": 1, "a": 2, "c": "{\"a\": 3}"}"#).is_ok());
        assert!(parse(r#"{"sites": [], "sites": [[0, 0]]}"#).is_err());
        assert!(parse("{").is_err());
    }
}
