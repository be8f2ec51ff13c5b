//! Newton corrector and pseudo-arc-length continuation.
