//! Case values as short TOML text: `1e-3` rather than `0.001`, matrices one
//! row a line. Used by the template, the error messages and the tests that
//! hold the key table's defaults to [`Case::default`](super::Case::default).

use std::num::FpCategory;
use toml::Value;

/// A float as TOML: `0.0`, `4.0`, `1.75`, `1e-3`, `1e8`.
pub fn float(x: f64) -> String {
    match x.classify() {
        FpCategory::Nan => "nan".into(),
        FpCategory::Infinite if x > 0.0 => "inf".into(),
        FpCategory::Infinite => "-inf".into(),
        FpCategory::Zero => format!("{x:?}"),
        _ if (0.01..1e5).contains(&x.abs()) => format!("{x:?}"),
        _ => format!("{x:e}"),
    }
}

/// A value on one line: `[1, 2]`, `{ dofs = [1, 2], stiffness = 2e6 }`.
pub fn inline(value: &Value) -> String {
    match value {
        Value::Float(x) => float(*x),
        Value::Array(items) => {
            let items: Vec<String> = items.iter().map(inline).collect();
            format!("[{}]", items.join(", "))
        }
        Value::Table(table) => {
            let items: Vec<String> = table
                .iter()
                .map(|(k, v)| format!("{k} = {}", inline(v)))
                .collect();
            format!("{{ {} }}", items.join(", "))
        }
        other => other.to_string(),
    }
}

/// A value as a key's right-hand side: a list of lists or of tables (a
/// matrix, springs) one entry a line, anything else [`inline`].
pub fn block(value: &Value) -> String {
    match value {
        Value::Array(items)
            if !items.is_empty()
                && items
                    .iter()
                    .all(|v| matches!(v, Value::Array(_) | Value::Table(_))) =>
        {
            let mut out = String::from("[\n");
            for item in items {
                out.push_str(&format!("    {},\n", inline(item)));
            }
            out.push(']');
            out
        }
        other => inline(other),
    }
}

/// The value at a dotted path (`model.damping.ratio`) of a case as TOML.
pub fn lookup<'a>(root: &'a Value, path: &str) -> Option<&'a Value> {
    path.split('.')
        .try_fold(root, |value, part| value.get(part))
}

/// TOML text of one value (`[[1.0, 0.0], [0.0, 1.0]]`) as a value.
pub fn parse_value(text: &str) -> Option<Value> {
    toml::from_str::<toml::Table>(&format!("x = {text}"))
        .ok()?
        .remove("x")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_are_short_and_exact() {
        for (x, s) in [
            (0.0, "0.0"),
            (4.0, "4.0"),
            (1.75, "1.75"),
            (0.05, "0.05"),
            (1e-3, "1e-3"),
            (5e-5, "5e-5"),
            (1e8, "1e8"),
            (2.5, "2.5"),
            (-12.5, "-12.5"),
            (10000.0, "10000.0"),
        ] {
            assert_eq!(float(x), s);
        }
    }

    #[test]
    fn matrices_are_one_row_a_line_and_parse_back() {
        let text = "[[1.0, 0.0], [0.0, 2e6]]";
        let value = parse_value(text).unwrap();
        assert_eq!(inline(&value), text);
        let rows = block(&value);
        assert_eq!(rows, "[\n    [1.0, 0.0],\n    [0.0, 2e6],\n]");
        assert_eq!(parse_value(&rows), Some(value));
        assert_eq!(block(&parse_value("[]").unwrap()), "[]");
        let quoted = parse_value("\"dir/m \\\"x\\\".mtx\"").unwrap();
        assert_eq!(parse_value(&inline(&quoted)), Some(quoted));
    }
}
