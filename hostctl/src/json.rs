//! A minimal JSON object writer for `--json` output (one object per line).

use std::fmt::Write as _;

/// Builds one JSON object, keys in insertion order.
#[derive(Debug, Default)]
pub struct Object {
    text: String,
}

impl Object {
    /// An empty object.
    pub fn new() -> Self {
        Self::default()
    }

    fn key(&mut self, key: &str) {
        self.text.push(if self.text.is_empty() { '{' } else { ',' });
        string_into(&mut self.text, key);
        self.text.push(':');
    }

    /// Adds an integer member.
    pub fn int(mut self, key: &str, value: impl Into<i64>) -> Self {
        self.key(key);
        let _ = write!(self.text, "{}", value.into());
        self
    }

    /// Adds a number member; non-finite values become `null`.
    pub fn num(self, key: &str, value: f32) -> Self {
        self.raw(key, &number(value))
    }

    /// Adds a string member.
    pub fn str(mut self, key: &str, value: &str) -> Self {
        self.key(key);
        string_into(&mut self.text, value);
        self
    }

    /// Adds a boolean member.
    pub fn bool(self, key: &str, value: bool) -> Self {
        self.raw(key, if value { "true" } else { "false" })
    }

    /// Adds a member whose value is already JSON text (an array or object).
    pub fn raw(mut self, key: &str, json: &str) -> Self {
        self.key(key);
        self.text.push_str(json);
        self
    }

    /// The finished object text.
    pub fn finish(mut self) -> String {
        if self.text.is_empty() {
            self.text.push('{');
        }
        self.text.push('}');
        self.text
    }
}

/// `value` as a JSON number; non-finite values become `null`.
pub fn number(value: f32) -> String {
    if value.is_finite() {
        value.to_string()
    } else {
        "null".to_owned()
    }
}

/// A JSON array of already-encoded elements.
pub fn array<I: IntoIterator<Item = String>>(items: I) -> String {
    let items: Vec<String> = items.into_iter().collect();
    format!("[{}]", items.join(","))
}

/// `s` as a quoted JSON string.
pub fn string(s: &str) -> String {
    let mut out = String::new();
    string_into(&mut out, s);
    out
}

/// Appends `s` as a quoted JSON string.
fn string_into(out: &mut String, s: &str) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn objects_keep_member_order() {
        let text = Object::new()
            .int("device", 1u8)
            .str("register", "REGDS_DRIVE_REQSPEED")
            .num("value", 999.9082)
            .num("bad", f32::NAN)
            .raw("ids", &array(["1".to_string(), "2".to_string()]))
            .finish();
        assert_eq!(
            text,
            r#"{"device":1,"register":"REGDS_DRIVE_REQSPEED","value":999.9082,"bad":null,"ids":[1,2]}"#
        );
    }

    #[test]
    fn strings_are_escaped() {
        let text = Object::new().str("s", "a\"b\\c\nd\u{1}°").finish();
        assert_eq!(text, r#"{"s":"a\"b\\c\nd\u0001°"}"#);
        assert_eq!(Object::new().finish(), "{}");
        assert_eq!(string("x\ty"), r#""x\ty""#);
    }
}
