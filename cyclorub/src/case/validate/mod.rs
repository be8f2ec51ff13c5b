//! Checks of a case's values before any work: the rules of the key table
//! ([`super::keys`]), one generic check per rule on the case as TOML values,
//! then the checks of the code that consumes a value (the casing, the
//! contact law), called here with their keys.

use super::error::number_text;
use super::keys::{Key, Rule, Table, When, TABLES};
use super::text::{inline, lookup};
use super::{invalid, Case, CaseError};
use crate::model::SectorModel;
use toml::Value;

impl Case {
    /// The case as TOML values, as the key table's rules read it.
    pub fn to_value(&self) -> Result<Value, CaseError> {
        Value::try_from(self).map_err(|error| {
            invalid(
                "case",
                "(not representable in TOML)",
                format!("{error}; file names must be valid UTF-8"),
            )
        })
    }

    /// Checks every value that serde cannot, naming the key, the value and
    /// what is allowed: the rules of the key table ([`super::keys::TABLES`]),
    /// then the casing and the contact law, whose constructors check their
    /// own values. Call before any work.
    ///
    /// The values of `[model]` are checked when the model is built
    /// ([`crate::model::ModelSpec::build`]), the case against the built model
    /// by [`Case::check_model`], and the memory the sizes take by the
    /// harmonic balance problem: each names its key ([`crate::run::prepare`] calls
    /// them all before any work).
    pub fn validate(&self) -> Result<(), CaseError> {
        let root = self.to_value()?;
        // The keys other rules compare with first, so that a bad value is
        // blamed on its own key (time_samples = 0, not casing.order).
        let referenced: Vec<&str> = TABLES
            .iter()
            .flat_map(|t| t.keys)
            .flat_map(|k| k.rules)
            .filter_map(|r| rule_key(*r))
            .collect();
        for first in [true, false] {
            for table in TABLES {
                for key in table.keys {
                    if referenced.contains(&table.path(key).as_str()) == first {
                        check_key(&root, table, key)?;
                    }
                }
            }
        }
        self.casing()?;
        self.contact_model()?;
        self.check_output()?;
        self.mistuning_deviations()?;
        self.check_blade()?;
        Ok(())
    }

    /// Keys given but not used as the case stands, each named with why
    /// (a warning, not a refusal: the value is kept in run.json and other
    /// commands may take it): `stability.harmonics` with `stability.enabled
    /// = false`, which only `cyclorub stability` on the results takes.
    pub fn unused_keys(&self) -> Vec<String> {
        let mut unused = Vec::new();
        if let (false, Some(harmonics)) = (self.stability.enabled, self.stability.harmonics) {
            unused.push(format!(
                "stability.harmonics = {harmonics} is not used by the run: stability.enabled = \
                 false, so no point is checked (only `cyclorub stability RESULTS` takes it); \
                 set enabled = true, or remove the key"
            ));
        }
        unused
    }

    /// The `[output]` table: a folder named, each sector reported once.
    fn check_output(&self) -> Result<(), CaseError> {
        if self.output.directory.as_os_str().is_empty() {
            return Err(invalid(
                "output.directory",
                "\"\"",
                "name a results folder (relative to the working directory)",
            ));
        }
        let sectors = &self.output.sectors;
        if let Some((i, s)) = sectors
            .iter()
            .enumerate()
            .find(|(i, s)| sectors[..*i].contains(s))
        {
            return Err(invalid(
                "output.sectors",
                format!("{sectors:?}"),
                format!(
                    "sector {s} is listed twice (entry {}); list each sector once",
                    i + 1
                ),
            ));
        }
        Ok(())
    }

    /// Checks the case against its built model: `output.observed_dof` is a
    /// dof of a sector.
    pub fn check_model(&self, model: &SectorModel) -> Result<(), CaseError> {
        let dofs = model.dofs_per_sector();
        let dof = self.output.observed_dof;
        if !(1..=dofs).contains(&dof) {
            return Err(invalid(
                "output.observed_dof",
                dof,
                format!("a sector has dofs 1..={dofs}"),
            ));
        }
        let given = self.preload.static_forces.len();
        if given != 0 && given != dofs {
            return Err(invalid(
                "preload.static_forces",
                format!("{given} values"),
                format!("one force per dof of a sector: the model has {dofs}"),
            ));
        }
        if self.preload.centrifugal {
            self.preload_speed()?;
        }
        Ok(())
    }
}

/// A key written in a case file that its other settings leave unused.
#[derive(Clone, Debug, PartialEq)]
pub struct UnusedKey {
    /// The key, its value and the setting that would use it, in words.
    pub message: String,
    /// Why its value would be refused were the key in use (`None`: it
    /// would be accepted).
    pub refused: Option<String>,
}

/// Keys written in the case file `text` that its other settings leave
/// unused (a key of the other contact law, of another excitation kind…),
/// each named with the setting that would use it and checked as if it
/// were in use. A key left at its default value is not named: `cyclorub
/// init` writes every key so, and such a key says nothing the user meant.
pub fn keys_not_in_use(case: &Case, text: &str) -> Vec<UnusedKey> {
    let (Ok(written), Ok(root), Ok(defaults)) = (
        toml::from_str::<Value>(text),
        case.to_value(),
        Case::default().to_value(),
    ) else {
        return Vec::new();
    };
    let mut unused = Vec::new();
    for table in TABLES {
        for key in table.keys {
            let path = table.path(key);
            let Some(value) = lookup(&written, &path) else {
                continue;
            };
            if holds(key.when, &root) || lookup(&defaults, &path) == Some(value) {
                continue;
            }
            let (setting, wanted, negated) = match key.when {
                When::Is(k, v) => (k, v, false),
                When::IsNot(k, v) => (k, v, true),
                When::Always => continue,
            };
            let actual = lookup(&root, setting).map_or("absent".to_string(), inline);
            let refused = key
                .rules
                .iter()
                .try_for_each(|rule| check(*rule, &path, value, key.unit, &root))
                .err()
                .map(|error| error.to_string())
                .or_else(|| outside_allowed(key, value));
            unused.push(UnusedKey {
                message: format!(
                    "{path} = {} is not used: it applies only with {setting} {} \
                     \"{wanted}\", and the case has {setting} = {actual}",
                    inline(value),
                    if negated { "other than" } else { "=" },
                ),
                refused,
            });
        }
    }
    unused
}

/// Why a number of `value` is outside what `key` allows, read from its
/// stated bound (`> 0`, `≥ 0`) and finiteness: the check of a key whose
/// rule is its setting's own (a contact law's), which does not run while
/// the key is unused.
fn outside_allowed(key: &Key, value: &Value) -> Option<String> {
    numbers(value).into_iter().find_map(|x| {
        let outside = match key.allowed {
            "> 0" => x <= 0.0,
            "≥ 0" => x < 0.0,
            _ => false,
        };
        if !x.is_finite() {
            Some(format!("{x} is not a finite number"))
        } else {
            outside.then(|| format!("{x} is not {}", key.allowed))
        }
    })
}

/// Whether a key is in use.
fn holds(when: When, root: &Value) -> bool {
    let is = |key: &str, value: &str| lookup(root, key).and_then(Value::as_str) == Some(value);
    match when {
        When::Always => true,
        When::Is(key, value) => is(key, value),
        When::IsNot(key, value) => !is(key, value),
    }
}

/// The rules of one key, when it is set and in use.
fn check_key(root: &Value, table: &Table, key: &Key) -> Result<(), CaseError> {
    let path = table.path(key);
    match lookup(root, &path) {
        Some(value) if holds(key.when, root) => key
            .rules
            .iter()
            .try_for_each(|rule| check(*rule, &path, value, key.unit, root)),
        _ => Ok(()),
    }
}

fn number(value: &Value) -> Option<f64> {
    match value {
        Value::Float(x) => Some(*x),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// The numbers of a value: itself, or a list's entries.
fn numbers(value: &Value) -> Vec<f64> {
    match value {
        Value::Array(items) => items.iter().filter_map(number).collect(),
        other => number(other).into_iter().collect(),
    }
}

/// One rule on the value of `path`; `root` holds the keys it refers to.
#[allow(clippy::float_cmp)] // `Differs`, `CountOf`: an exact (in)equality is the rule
fn check(rule: Rule, path: &str, value: &Value, unit: &str, root: &Value) -> Result<(), CaseError> {
    let each = |ok: &dyn Fn(f64) -> bool, allowed: String| match numbers(value)
        .into_iter()
        .find(|&x| !ok(x))
    {
        Some(x) => Err(invalid(path, number_text(x), allowed)),
        None => Ok(()),
    };
    let with_unit = |allowed: &str| match unit {
        "" => allowed.to_string(),
        unit => format!("{allowed} ({unit})"),
    };
    // The value of the key a rule compares with (absent: nothing to compare).
    let other = rule_key(rule)
        .and_then(|key| lookup(root, key))
        .and_then(number);
    match (rule, other) {
        (Rule::Finite, _) => each(&|x| x.is_finite(), with_unit("must be a finite number")),
        (Rule::NonNegative, _) => each(
            &|x| x.is_finite() && x >= 0.0,
            with_unit("must be a finite number ≥ 0"),
        ),
        (Rule::Positive, _) => each(
            &|x| x.is_finite() && x > 0.0,
            with_unit("must be a finite number > 0"),
        ),
        (Rule::AtLeast(n), _) => each(&|x| x >= n as f64, format!("must be at least {n}")),
        (Rule::Dofs, _) if value.as_array().is_some_and(Vec::is_empty) => {
            Err(invalid(path, "[]", "give at least one dof (1-based)"))
        }
        (Rule::Dofs, _) if numbers(value).iter().any(|&x| x < 1.0) => {
            Err(invalid(path, inline(value), "dofs are numbered from 1"))
        }
        (Rule::Below(key), Some(n)) => each(
            &|x| x < n,
            format!("must be in 0..={} (below {key} = {n})", n - 1.0),
        ),
        (Rule::BelowHalf(key, why), Some(n)) => each(
            &|x| 2.0 * x < n,
            format!("must be below {key} / 2 = {} {why}", (n / 2.0).ceil()),
        ),
        (Rule::OneTo(key), Some(n)) => each(
            &|x| (1.0..=n).contains(&x),
            format!("must be in 1..={n} ({key} = {n})"),
        ),
        (Rule::CountOf(key), Some(n)) => {
            let count = value.as_array().map_or(1, Vec::len);
            if count as f64 == n {
                Ok(())
            } else {
                Err(invalid(
                    path,
                    format!("{count} values"),
                    format!("needs one value each, as many as {key} = {n}"),
                ))
            }
        }
        (Rule::AboveTwice(key), Some(n)) => each(
            &|x| x >= 2.0 * n + 1.0,
            format!("must be at least 2 × {key} + 1 = {}", 2.0 * n + 1.0),
        ),
        (Rule::AtMost(key), Some(n)) => each(&|x| x <= n, format!("must not exceed {key} = {n}")),
        (Rule::NoMoreThan(n), _) => each(&|x| x <= n, format!("must not exceed {n:e}")),
        (Rule::Differs(key, why), Some(n)) => {
            each(&|x| x != n, format!("{why}: must differ from {key} = {n}"))
        }
        // `OneOf`: serde's; `CheckedBy`: the consumer's; or nothing to compare with.
        _ => Ok(()),
    }
}

/// The key a rule compares with, if any.
fn rule_key(rule: Rule) -> Option<&'static str> {
    match rule {
        Rule::Below(key)
        | Rule::BelowHalf(key, _)
        | Rule::OneTo(key)
        | Rule::CountOf(key)
        | Rule::AtMost(key)
        | Rule::AboveTwice(key)
        | Rule::Differs(key, _) => Some(key),
        _ => None,
    }
}

#[cfg(test)]
mod tests;
