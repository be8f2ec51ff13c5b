//! A case rendered as a commented case file from the key table
//! ([`TABLES`]): every key in order, its comment made from the table, its
//! value from the case or, when absent, an example commented out.

use cyclorub::case::keys::{Key, Table, TABLES};
use cyclorub::case::text::{block, float, lookup, parse_value};
use cyclorub::case::{Case, CaseError};
use cyclorub::forced_response::excited_frequency;
use cyclorub::model::{LumpedSector, ModelKind, SpringLink, DEFAULT_SYMMETRY_TOLERANCE};
use std::path::Path;

/// Renders any case as a commented case file that parses back to it, with
/// `header` as its first comment lines: every key of the key table
/// ([`TABLES`]) in order, its comment made from the table, its value from
/// `case` (or, when absent, an example commented out). Fails only for a
/// case that TOML cannot hold (a file name that is not UTF-8).
pub fn render(case: &Case, header: &[String]) -> Result<String, CaseError> {
    let root = case.to_value()?;
    let range = automatic_range(case);
    let mut out = String::new();
    for line in header {
        out.push_str(&format!("# {line}\n"));
    }
    out.push_str(
        "#\n\
         # Every key is shown with its value and a comment: what it is, its unit, what is allowed.\n\
         # A key left out takes the default value of `cyclorub init`. Keys shown commented out\n\
         # (`# key = value`) are absent: the rule in their comment applies. Dofs and sectors are\n\
         # numbered from 1. Natural frequencies: cyclorub modes CASE.toml; basis sizes: cyclorub plan;\n\
         # the forced response: cyclorub run CASE.toml.\n",
    );
    for table in TABLES {
        out.push_str(&format!("\n# {}\n[{}]\n", table.doc, table.name));
        for key in table.keys {
            let path = table.path(key);
            let note = match (path.as_str(), range) {
                ("continuation.start_hz", Some((start, _))) => format!(", here {} Hz", hz(start)),
                ("continuation.end_hz", Some((_, end))) => format!(", here {} Hz", hz(end)),
                _ => String::new(),
            };
            out.push_str(&format!("# {}\n", key.comment(&note)));
            let (prefix, value) = match lookup(&root, &path) {
                Some(value) => ("", block(value)),
                None => ("# ", example(table, key, range)),
            };
            for line in format!("{} = {value}", key.name).lines() {
                out.push_str(&format!("{prefix}{line}\n"));
            }
        }
    }
    Ok(out)
}

/// The value shown commented out for a key absent from a case: the key
/// table's example, or one made here from the defaults it stands for.
pub(super) fn example(table: &Table, key: &Key, range: Option<(f64, f64)>) -> String {
    let auto = |i: usize| float(range.map_or(100.0 * (1.0 + i as f64), |r| hz([r.0, r.1][i])));
    match table.path(key).as_str() {
        "model.symmetry_tolerance" => float(DEFAULT_SYMMETRY_TOLERANCE),
        "model.masses" => floats(&LumpedSector::academic().masses),
        "model.springs" => academic_springs(),
        "continuation.start_hz" => auto(0),
        "continuation.end_hz" => auto(1),
        _ => parse_value(key.example).map_or_else(|| key.example.to_string(), |v| block(&v)),
    }
}

fn floats(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(|&v| float(v)).collect();
    format!("[{}]", items.join(", "))
}

/// The springs of the paper's academic sector, as a case file writes them.
fn academic_springs() -> String {
    let mut out = String::from("[\n");
    for spring in LumpedSector::academic().springs {
        let (dofs, link) = match spring.link {
            SpringLink::Within(a, b) => (format!("[{}, {}]", a + 1, b + 1), ""),
            SpringLink::NextSector(a, b) => (
                format!("[{}, {}]", a + 1, b + 1),
                ", link = \"next_sector\"",
            ),
            SpringLink::Ground(a) => (format!("[{}]", a + 1), ", link = \"ground\""),
        };
        out.push_str(&format!(
            "    {{ dofs = {dofs}, stiffness = {}{link} }},\n",
            float(spring.stiffness)
        ));
    }
    out.push(']');
    out
}

/// The automatic frequency range of a case (Hz), when its model builds:
/// 0.95 and 1.10 × the first natural frequency of the excited nodal diameter.
pub(super) fn automatic_range(case: &Case) -> Option<(f64, f64)> {
    if case.model.kind != ModelKind::Academic {
        return None;
    }
    let model = case.model.build(Path::new(".")).ok()?;
    let f = excited_frequency(case, &model).ok()?;
    Some((0.95 * f, 1.10 * f))
}

/// Rounds a frequency for display (Hz, two decimals).
fn hz(f: f64) -> f64 {
    (f * 100.0).round() / 100.0
}
