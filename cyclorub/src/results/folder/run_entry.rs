//! Setting one top-level entry of a results folder's `run.json` after its
//! run (`cyclorub branches` records its branches there), the rest of the
//! file kept as written: its keys in their order, its numbers as printed
//! (a `serde_json::Value` would sort the keys).

use crate::results::bifurcated::{merge, BranchSummary};
use crate::results::ResultsError;
use std::path::Path;

/// Sets `run.json`'s `branches` entry of the results folder `folder` to its
/// earlier records merged with `new` (a branch point switched at again
/// replaces its record; an earlier entry this version cannot read is
/// replaced whole); returns the entry written.
pub fn record_branches_in_run_file(
    folder: &Path,
    new: &[BranchSummary],
) -> Result<Vec<BranchSummary>, ResultsError> {
    let path = folder.join("run.json");
    let bad = |message: String| ResultsError::Read {
        path: path.clone(),
        message,
    };
    let text = std::fs::read_to_string(&path).map_err(|e| bad(e.to_string()))?;
    let run: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| bad(format!("not JSON: {e}")))?;
    let earlier: Vec<BranchSummary> = run
        .get("branches")
        .and_then(|b| serde_json::from_value(b.clone()).ok())
        .unwrap_or_default();
    let all = merge(&earlier, new);
    let value = serde_json::to_value(&all).map_err(|e| ResultsError::Input(e.to_string()))?;
    let text =
        set_entry(&text, "branches", &value).ok_or_else(|| bad("not a JSON object".into()))?;
    // Through a temporary file, so that run.json is always whole.
    let partial = path.with_extension("json.partial");
    std::fs::write(&partial, text).map_err(crate::results::io(&partial))?;
    std::fs::rename(&partial, &path).map_err(crate::results::io(&path))?;
    Ok(all)
}

/// `text`, a JSON object, with its top-level entry `key` set to `value`
/// (pretty-printed, indented by two spaces): an entry of that key removed,
/// the new one added last, every other byte kept; `None` when `text` is not
/// an object.
pub(crate) fn set_entry(text: &str, key: &str, value: &serde_json::Value) -> Option<String> {
    // The object's braces and the commas between its entries.
    let (mut depth, mut in_string, mut escaped) = (0usize, false, false);
    let (mut open, mut close, mut commas) = (None, None, Vec::new());
    for (i, c) in text.char_indices() {
        if in_string {
            match (escaped, c) {
                (true, _) => escaped = false,
                (false, '\\') => escaped = true,
                (false, '"') => in_string = false,
                _ => {}
            }
            continue;
        }
        match c {
            '"' => in_string = true,
            '{' | '[' => {
                if depth == 0 {
                    if c != '{' {
                        return None;
                    }
                    open = Some(i);
                }
                depth += 1;
            }
            '}' | ']' => {
                depth = depth.checked_sub(1)?;
                if depth == 0 {
                    close = Some(i);
                    break;
                }
            }
            ',' if depth == 1 => commas.push(i),
            _ => {}
        }
    }
    let (open, close) = (open?, close?);
    let bounds: Vec<usize> = std::iter::once(open)
        .chain(commas)
        .chain(std::iter::once(close))
        .collect();
    let mut entries: Vec<&str> = Vec::new();
    for pair in bounds.windows(2) {
        let entry = &text[pair[0] + 1..pair[1]];
        if entry.trim().is_empty() {
            continue;
        }
        let name = serde_json::Deserializer::from_str(entry)
            .into_iter::<String>()
            .next()?
            .ok()?;
        if name != key {
            entries.push(entry.trim_end());
        }
    }
    let pretty = serde_json::to_string_pretty(value)
        .ok()?
        .replace('\n', "\n  ");
    let name = serde_json::to_string(key).ok()?;
    entries.push("");
    let mut out = String::from(&text[..=open]);
    out.push_str(&entries[..entries.len() - 1].join(","));
    if entries.len() > 1 {
        out.push(',');
    }
    out.push_str(&format!("\n  {name}: {pretty}\n"));
    out.push_str(&text[close..]);
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_entry_is_set_last_and_the_rest_kept_as_written() {
        let text = "{\n  \"status\": \"finished\",\n  \"branches\": [1],\n  \"case\": {\"z\": 1, \"a\": \"}, [\\\"\"}\n}\n";
        let value = serde_json::json!([{"class": 3}]);
        let set = set_entry(text, "branches", &value).expect("an object");
        assert_eq!(
            set,
            "{\n  \"status\": \"finished\",\n  \"case\": {\"z\": 1, \"a\": \"}, [\\\"\"},\n  \"branches\": [\n    {\n      \"class\": 3\n    }\n  ]\n}\n"
        );
        let back: serde_json::Value = serde_json::from_str(&set).expect("JSON");
        assert_eq!(back["branches"], value);
        assert_eq!(back["case"]["a"], "}, [\"");
        // Set again: replaced, not repeated.
        assert_eq!(
            set_entry(&set, "branches", &value).as_deref(),
            Some(set.as_str())
        );
        assert_eq!(
            set_entry("{}", "branches", &serde_json::json!(1)).as_deref(),
            Some("{\n  \"branches\": 1\n}")
        );
        assert_eq!(set_entry("[1]", "branches", &value), None);
    }
}
