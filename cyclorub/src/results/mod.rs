//! Result files: `branch.csv`, `run.json`.
