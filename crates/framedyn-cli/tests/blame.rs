//! Scene errors name the field that is wrong: every numeric field of every
//! embedded scene, set to each of a set of bad values, either still gives a
//! valid scene or an error whose path is that field — or, where a relation
//! between fields fails (a coordinate and the radius, the span and the
//! step), whose message names the field with its value.

use framedyn::scenes::{Scene, SceneError, EXAMPLES};

/// `(line index, dotted key, value text)` of every `key = number` line
/// (scalars only) of a TOML text.
fn numeric_lines(text: &str) -> Vec<(usize, String)> {
    let mut table = String::new();
    let mut counts = std::collections::HashMap::<String, usize>::new();
    let mut out = Vec::new();
    for (i, l) in text.lines().enumerate() {
        let t = l.trim();
        if let Some(n) = t.strip_prefix("[[").and_then(|r| r.strip_suffix("]]")) {
            let k = counts.entry(n.to_string()).or_insert(0);
            table = format!("{n}[{k}]");
            *k += 1;
        } else if let Some(n) = t.strip_prefix('[').and_then(|r| r.strip_suffix(']')) {
            table = n.to_string();
        } else if let Some((k, v)) = t.split_once('=') {
            if v.trim().parse::<f64>().is_ok() {
                out.push((i, format!("{table}.{}", k.trim())));
            }
        }
    }
    out
}

fn error_path(e: &SceneError) -> String {
    match e {
        SceneError::Invalid { path, .. } | SceneError::Parse { path, .. } => path.clone(),
        other => format!("({other})"),
    }
}

#[test]
fn errors_name_the_mutated_field() {
    let bad = ["nan", "inf", "-inf", "-1.0", "0.0", "1e308", "-1e308", "1e-300"];
    let mut wrong = Vec::new();
    let mut checked = 0;
    for (name, text) in EXAMPLES {
        for (line, key) in numeric_lines(text) {
            for v in bad {
                let mutated: String = text
                    .lines()
                    .enumerate()
                    .map(|(i, l)| if i == line { format!("{} = {v}", l.split_once('=').unwrap().0.trim()) } else { l.to_string() })
                    .collect::<Vec<_>>()
                    .join("\n");
                let Err(e) = Scene::from_str_auto(&mutated).and_then(|s| s.build().map(|_| ())) else { continue };
                checked += 1;
                let path = error_path(&e);
                let norm = |p: &str| p.replace(['[', ']'], ".").replace("..", ".");
                let (p, k) = (norm(&path), norm(&key));
                // The path is the field, or (for a relation between fields)
                // the message names it with its value.
                if !(p == k || p.starts_with(&format!("{k}.")) || e.to_string().contains(&format!("{key} = "))) {
                    wrong.push(format!("{name}: {key} = {v} → `{path}`: {e}"));
                }
            }
        }
    }
    for w in &wrong {
        eprintln!("{w}");
    }
    eprintln!("{} of {checked} errors name another field", wrong.len());
    assert!(wrong.is_empty());
}
