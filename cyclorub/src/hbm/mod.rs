//! Harmonic balance: unknown layout, condensed linear part, AFT-CP and residual.
