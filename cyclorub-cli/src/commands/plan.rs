//! `cyclorub plan`: what each spectral basis keeps, before running anything.

use super::{outln, CliError};
use cyclorub_app::plan::tables::{plan_tables, sweep_table};
use cyclorub_app::plan::{plan_row, sweep, ExcitationKind, PlanCase, PlanRow, PlanRule};

/// Excitation kinds on the command line.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Excitation {
    /// Eq. (48): one backward traveling wave.
    Traveling,
    /// Eq. (75): a standing wave (the paper's tables).
    Standing,
    /// Eq. (86): 90 % backward and 10 % forward.
    Mixed,
}

/// Rules on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum RuleChoice {
    /// The paper's own choice of basis.
    Paper,
    /// The symmetry rule (docs/design.md §3).
    Symmetry,
    /// Both, paper first.
    Both,
}

/// Arguments of `cyclorub plan`.
#[derive(clap::Args)]
pub struct PlanArgs {
    /// Number of sectors N (at least 1). Required, unless --sweep-sectors.
    #[arg(
        long,
        value_name = "N",
        required_unless_present = "sweep_sectors",
        allow_negative_numbers = true,
        value_parser = count
    )]
    pub sectors: Option<usize>,
    /// Number of harmonics N_h (at least 1). Required.
    #[arg(long, value_name = "NH", allow_negative_numbers = true, value_parser = count)]
    pub harmonics: usize,
    /// Contact dofs per sector (at least 1). Required, unless --sweep-sectors.
    #[arg(
        long = "contact-dofs",
        value_name = "n",
        required_unless_present = "sweep_sectors",
        allow_negative_numbers = true,
        value_parser = count
    )]
    pub contact_dofs: Option<usize>,
    /// Engine order h of the excitation, in 0..N (default: every order 0..=N/2).
    #[arg(
        long = "engine-order",
        value_name = "h",
        conflicts_with = "sweep_sectors",
        allow_negative_numbers = true,
        value_parser = count
    )]
    pub engine_order: Option<usize>,
    /// Kind of excitation.
    #[arg(long, value_enum, default_value = "standing")]
    pub excitation: Excitation,
    /// Diametral order of the casing, synchronous with rotation (0: circular).
    #[arg(
        long = "casing-order",
        value_name = "hc",
        allow_negative_numbers = true,
        value_parser = count
    )]
    pub casing_order: Option<usize>,
    /// Which rule to show.
    #[arg(long, value_enum, default_value = "both")]
    pub rule: RuleChoice,
    /// Mean reductions for every N in A..B (both included) instead of a table.
    #[arg(
        long = "sweep-sectors",
        value_name = "A..B",
        conflicts_with = "sectors"
    )]
    pub sweep_sectors: Option<String>,
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
}

/// A non-negative integer argument (ranges are checked after parsing).
fn count(text: &str) -> Result<usize, String> {
    text.trim()
        .parse()
        .map_err(|_| format!("expected a non-negative integer, got {text:?}"))
}

impl From<Excitation> for ExcitationKind {
    fn from(e: Excitation) -> Self {
        match e {
            Excitation::Traveling => Self::Traveling,
            Excitation::Standing => Self::Standing,
            Excitation::Mixed => Self::Mixed,
        }
    }
}

/// Parses `A..B` or `A..=B` (both ends included).
fn parse_range(text: &str) -> Result<(usize, usize), CliError> {
    let bad = || {
        CliError::usage(format!(
            "--sweep-sectors {text:?} is not valid: expected A..B with integers 1 <= A <= B"
        ))
    };
    let (a, b) = text.split_once("..").ok_or_else(bad)?;
    let b = b.strip_prefix('=').unwrap_or(b);
    let a: usize = a.trim().parse().map_err(|_| bad())?;
    let b: usize = b.trim().parse().map_err(|_| bad())?;
    Ok((a, b))
}

fn rules(choice: RuleChoice) -> Vec<PlanRule> {
    match choice {
        RuleChoice::Paper => vec![PlanRule::Paper],
        RuleChoice::Symmetry => vec![PlanRule::Symmetry],
        RuleChoice::Both => vec![PlanRule::Paper, PlanRule::Symmetry],
    }
}

fn to_json<T: serde::Serialize>(value: &T) -> Result<String, CliError> {
    serde_json::to_string_pretty(value).map_err(|e| CliError::failure(e.to_string()))
}

/// Runs `cyclorub plan`.
pub fn execute(args: PlanArgs) -> Result<(), CliError> {
    let excitation = ExcitationKind::from(args.excitation);
    if let Some(range) = &args.sweep_sectors {
        let (from, to) = parse_range(range)?;
        let result = sweep(from, to, args.harmonics, excitation, args.casing_order)?;
        let text = if args.json {
            to_json(&result)?
        } else {
            sweep_table(&result)
        };
        outln!("{text}");
        return Ok(());
    }
    let sectors = args.sectors.unwrap_or(0);
    let base = PlanCase {
        sectors,
        harmonics: args.harmonics,
        contact_dofs: args.contact_dofs.unwrap_or(0),
        engine_order: args.engine_order.unwrap_or(0),
        excitation,
        casing_order: args.casing_order,
    };
    base.validate()?;
    let orders: Vec<usize> = match args.engine_order {
        Some(h) => vec![h],
        None => (0..=sectors / 2).collect(),
    };
    let mut tables: Vec<(PlanRule, Vec<PlanRow>)> = Vec::new();
    for rule in rules(args.rule) {
        let rows = orders
            .iter()
            .map(|&engine_order| {
                plan_row(
                    &PlanCase {
                        engine_order,
                        ..base
                    },
                    rule,
                )
            })
            .collect::<Result<Vec<_>, _>>()?;
        tables.push((rule, rows));
    }
    if args.json {
        let all: Vec<&PlanRow> = tables.iter().flat_map(|(_, rows)| rows).collect();
        outln!("{}", to_json(&all)?);
    } else {
        outln!(
            "{}",
            plan_tables(&base, &tables, args.engine_order.is_some())
        );
    }
    Ok(())
}
