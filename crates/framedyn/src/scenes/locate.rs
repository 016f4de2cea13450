//! Line and column of a field path (`a.b[2].c`) in the scene text.

use super::error::Location;

/// 1-based line and column (in characters) of a byte offset.
pub(crate) fn offset_to_location(text: &str, offset: usize) -> Location {
    let offset = offset.min(text.len());
    let before = &text[..floor_char_boundary(text, offset)];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map(|i| i + 1).unwrap_or(0);
    let column = before[line_start..].chars().count() + 1;
    Location { line, column }
}

/// The dotted key of the TOML line that holds byte `offset`
/// (`output.every`, `events[1].value`), from the nearest table header above
/// it and the key before `=` on that line: for errors the TOML parser
/// raises before any field is deserialised (an integer beyond 64 bits).
pub fn toml_key_at(text: &str, offset: usize) -> Option<String> {
    let offset = floor_char_boundary(text, offset.min(text.len()));
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let line = text[line_start..].lines().next().unwrap_or("");
    let key = line.split_once('=')?.0.trim().trim_matches('"').trim_matches('\'');
    if key.is_empty() || key.starts_with('[') || key.starts_with('#') {
        return None;
    }
    let mut table: Option<String> = None;
    let mut counts: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
    for l in text[..line_start].lines() {
        let l = l.trim();
        if let Some(name) = l.strip_prefix("[[").and_then(|r| r.split_once("]]")).map(|(n, _)| n.trim().to_string()) {
            let k = counts.entry(name.clone()).or_insert(0);
            table = Some(format!("{name}[{k}]"));
            *k += 1;
        } else if let Some(name) = l.strip_prefix('[').and_then(|r| r.split_once(']')).map(|(n, _)| n.trim().to_string()) {
            table = Some(name);
        }
    }
    Some(match table {
        Some(t) => format!("{t}.{key}"),
        None => key.to_string(),
    })
}

fn floor_char_boundary(s: &str, mut i: usize) -> usize {
    while i > 0 && !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

enum Seg<'a> {
    Key(&'a str),
    Index(usize),
}

fn segments(path: &str) -> Vec<Seg<'_>> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let mut rest = part;
        // Strip a trailing " (field)" note.
        if let Some(i) = rest.find(' ') {
            rest = &rest[..i];
        }
        let (key, mut idx) = match rest.find('[') {
            Some(i) => (&rest[..i], &rest[i..]),
            None => (rest, ""),
        };
        if !key.is_empty() {
            out.push(Seg::Key(key));
        }
        while let Some(end) = idx.find(']') {
            if let Ok(n) = idx[1..end].parse() {
                out.push(Seg::Index(n));
            }
            idx = &idx[end + 1..];
        }
    }
    out
}

/// The location of the value at `path` in a TOML document, or of the
/// deepest enclosing item that exists.
pub(crate) fn toml_path(text: &str, path: &str) -> Option<Location> {
    use toml_edit::{ImDocument, Item, Value};
    let doc = ImDocument::parse(text).ok()?;
    let mut best = None;
    let mut item: Option<&Item> = Some(doc.as_item());
    let mut value: Option<&Value> = None;
    for seg in segments(path) {
        match seg {
            Seg::Key(k) => {
                if let Some(v) = value {
                    let next = v.as_inline_table().and_then(|t| t.get(k));
                    match next {
                        Some(n) => {
                            best = n.span().or(best);
                            value = Some(n);
                        }
                        None => break,
                    }
                } else if let Some(it) = item {
                    let next = it.as_table_like().and_then(|t| t.get(k));
                    match next {
                        Some(n) => {
                            if let Some(sp) = n.span() {
                                best = Some(sp);
                            } else if let Some(t) = n.as_table() {
                                best = t.span().or(best);
                            }
                            if let Item::Value(v) = n {
                                value = Some(v);
                                item = None;
                            } else {
                                item = Some(n);
                            }
                        }
                        None => break,
                    }
                }
            }
            Seg::Index(i) => {
                if let Some(v) = value {
                    match v.as_array().and_then(|a| a.get(i)) {
                        Some(n) => {
                            best = n.span().or(best);
                            value = Some(n);
                        }
                        None => break,
                    }
                } else if let Some(it) = item {
                    match it.as_array_of_tables().and_then(|a| a.get(i)) {
                        Some(t) => {
                            best = t.span().or(best);
                            break;
                        }
                        None => break,
                    }
                }
            }
        }
    }
    best.map(|sp| offset_to_location(text, sp.start))
}

/// Best-effort location of `path` in JSON text: the keys are searched in order.
pub(crate) fn json_path(text: &str, path: &str) -> Option<Location> {
    let mut pos = 0usize;
    let mut found = None;
    for seg in segments(path) {
        if let Seg::Key(k) = seg {
            let needle = format!("\"{k}\"");
            match text[pos..].find(&needle) {
                Some(i) => {
                    pos += i;
                    found = Some(pos);
                    pos += needle.len();
                }
                None => break,
            }
        }
    }
    found.map(|o| offset_to_location(text, o))
}
