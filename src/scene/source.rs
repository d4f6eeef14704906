//! Where each key of a scene is written: maps byte spans of the TOML text to dotted key paths
//! and key paths to lines, so that every message can name the key and its line.

use std::ops::Range;
use toml::de::{DeTable, DeValue};

/// The keys of one TOML text with their spans.
#[derive(Debug, Default)]
pub struct SourceMap {
    text: String,
    /// (key path, span of the key, span of the value)
    entries: Vec<(String, Range<usize>, Range<usize>)>,
}

/// A 1-based (line, column) of a byte offset.
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut end = offset.min(text.len());
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    let before = &text[..end];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

impl SourceMap {
    /// Map a TOML text; a text that does not parse gives an empty map.
    pub fn new(text: &str) -> Self {
        let mut map = SourceMap {
            text: text.to_string(),
            entries: Vec::new(),
        };
        if let Ok(doc) = DeTable::parse(text) {
            map.walk_table(doc.get_ref(), "");
        }
        map
    }

    fn walk_table(&mut self, table: &DeTable<'_>, prefix: &str) {
        for (k, v) in table.iter() {
            let path = join(prefix, k.get_ref());
            self.entries.push((path.clone(), k.span(), v.span()));
            self.walk_value(v.get_ref(), &path);
        }
    }

    fn walk_value(&mut self, value: &DeValue<'_>, path: &str) {
        match value {
            DeValue::Table(t) => self.walk_table(t, path),
            DeValue::Array(a) => {
                for (i, item) in a.iter().enumerate() {
                    let p = format!("{path}[{i}]");
                    self.entries.push((p.clone(), item.span(), item.span()));
                    self.walk_value(item.get_ref(), &p);
                }
            }
            _ => {}
        }
    }

    /// The most specific key whose key or value span contains `span.start`.
    pub fn key_at(&self, span: &Range<usize>) -> Option<&str> {
        let at = span.start;
        self.entries
            .iter()
            .flat_map(|(p, k, v)| [(p, k), (p, v)])
            .filter(|(_, r)| r.start <= at && at < r.end.max(r.start + 1))
            .min_by_key(|(p, r)| (r.end - r.start, usize::MAX - p.len()))
            .map(|(p, _)| p.as_str())
    }

    /// Whether `key` (a dotted path) is written in the text itself.
    pub fn has(&self, key: &str) -> bool {
        self.entries.iter().any(|(p, _, _)| p == key)
    }

    /// The line where `key` (a dotted path) is written, if it is; else that of its closest
    /// written parent.
    pub fn line_of(&self, key: &str) -> Option<usize> {
        let mut k = key;
        loop {
            if let Some((_, span, _)) = self.entries.iter().find(|(p, _, _)| p == k) {
                return Some(line_column(&self.text, span.start).0);
            }
            k = &k[..k.rfind(['.', '['])?];
        }
    }
}

/// `prefix.key`, or `key` at the top.
pub fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "[scene]\nname = \"a\"\n\n[adhesion]\ngamma = 0.1\nz0 = 0.34\n\n[[schedule.segment]]\nkind = \"load\"\n[[schedule.segment]]\nkind = \"hold\"\ntime = 3\n";

    #[test]
    fn keys_map_to_their_lines_and_spans_to_their_keys() {
        let m = SourceMap::new(TEXT);
        assert_eq!(m.line_of("adhesion.gamma"), Some(5));
        assert_eq!(m.line_of("adhesion.z0"), Some(6));
        assert_eq!(m.line_of("schedule.segment[1].time"), Some(12));
        // a key that is not written falls back to its section
        assert_eq!(m.line_of("adhesion.law"), m.line_of("adhesion"));
        let at = TEXT.find("0.34").unwrap();
        assert_eq!(m.key_at(&(at..at + 4)), Some("adhesion.z0"));
        let at = TEXT.rfind("time").unwrap();
        assert_eq!(m.key_at(&(at..at + 4)), Some("schedule.segment[1].time"));
    }
}
