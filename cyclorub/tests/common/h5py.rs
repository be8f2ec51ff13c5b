//! The HDF5 C library's reading of a results file, through h5py: the
//! independent half of the results tests, skipped (and said so) where
//! Python or h5py is missing.

use std::path::Path;

/// Runs the Python `script` with `path` as its argument and parses what it
/// prints as JSON; `None` (with a line on stderr) when python3 or h5py is
/// not installed. Panics with Python's message when the script fails.
pub fn read_with_h5py(script: &str, path: &Path) -> Option<serde_json::Value> {
    let output = std::process::Command::new("python3")
        .arg("-c")
        .arg(script)
        .arg(path)
        .output();
    let output = match output {
        Ok(o) if o.status.success() => o,
        Ok(o) if String::from_utf8_lossy(&o.stderr).contains("No module named") => {
            eprintln!("h5py is not installed: the Python half is skipped");
            return None;
        }
        Ok(o) => panic!("h5py failed: {}", String::from_utf8_lossy(&o.stderr)),
        Err(_) => {
            eprintln!("python3 is not available: the Python half is skipped");
            return None;
        }
    };
    Some(serde_json::from_slice(&output.stdout).expect("the script prints JSON"))
}
