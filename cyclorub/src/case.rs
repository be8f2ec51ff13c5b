//! The case file (TOML): every input of a run, with the paper's defaults.
