//! The Python type of every case-file key, for the package's type stubs
//! (`python/cyclorub/_case.pyi`, written by `cyclorub-py/tools/stubs.py`
//! from [`key_types`]): from the key table's machine rules, else from the
//! value the default case holds, else from its template example, else
//! `Any`.

use cyclorub::case::keys::{Consumer, Key, Rule, TABLES};
use cyclorub::case::Case;
use pyo3::prelude::*;
use serde_json::Value;

/// The type of the rules' values, when a rule says it.
fn from_rules(key: &Key) -> Option<String> {
    key.rules.iter().find_map(|rule| {
        Some(match rule {
            Rule::OneOf(names) => {
                let quoted: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
                format!("Literal[{}]", quoted.join(", "))
            }
            Rule::Finite | Rule::NonNegative | Rule::Positive => {
                // A scalar that the casing also reads per contact dof.
                if key.rules.contains(&Rule::CheckedBy(Consumer::Casing)) {
                    "float | list[float]".into()
                } else {
                    "float".into()
                }
            }
            Rule::AtLeast(_) | Rule::Below(_) | Rule::BelowHalf(..) | Rule::AboveTwice(_) => {
                "int".into()
            }
            Rule::Dofs | Rule::OneTo(_) => "list[int]".into(),
            Rule::CountOf(_) => "list[float]".into(),
            _ => return None,
        })
    })
}

/// The type of a value of the default case.
fn from_value(value: &Value) -> Option<String> {
    Some(match value {
        Value::Bool(_) => "bool".into(),
        Value::Number(n) if n.is_f64() => "float".into(),
        Value::Number(_) => "int".into(),
        Value::String(_) => "str".into(),
        Value::Array(items) => match items.first() {
            Some(first) => format!("list[{}]", from_value(first)?),
            None => return None,
        },
        _ => return None,
    })
}

/// The type of a key's template example (TOML text), for a key the
/// default case leaves absent.
fn from_example(example: &str) -> Option<String> {
    let table: toml::Table = toml::from_str(&format!("x = {example}")).ok()?;
    from_value(&serde_json::to_value(table.get("x")?).ok()?)
}

/// `{dotted key: Python type}` of every key, `| None` where the key may
/// be absent (its default is a rule, or it is required by some use).
#[pyfunction]
pub fn key_types() -> Vec<(String, String)> {
    let default = serde_json::to_value(Case::default()).unwrap_or(Value::Null);
    TABLES
        .iter()
        .flat_map(|table| {
            let default = &default;
            table.keys.iter().map(move |key| {
                let path = table.path(key);
                let pointer = format!("/{}", path.replace('.', "/"));
                let value = default.pointer(&pointer);
                // A rule names the values; a list default holds several.
                let kind = from_rules(key)
                    .map(|kind| match value {
                        Some(Value::Array(_)) if !kind.starts_with("list[") => {
                            format!("list[{kind}]")
                        }
                        _ => kind,
                    })
                    .or_else(|| value.and_then(from_value))
                    .or_else(|| from_example(key.example))
                    .unwrap_or_else(|| "Any".into());
                let absent =
                    key.default.starts_with("absent") || key.default.starts_with("required");
                let kind = if absent && kind != "Any" {
                    format!("{kind} | None")
                } else {
                    kind
                };
                (path, kind)
            })
        })
        .collect()
}
