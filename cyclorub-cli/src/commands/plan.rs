//! `cyclorub plan`: what each spectral basis keeps, before running anything.

use super::CliError;
use cyclorub_app::plan::{
    plan_row, sweep, ExcitationKind, PlanCase, PlanError, PlanRow, PlanRule, SectorClass, Sweep,
};
use std::fmt::Write as _;

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
    /// The symmetry rule (DESIGN.md §3).
    Symmetry,
    /// Both, paper first.
    Both,
}

/// Arguments of `cyclorub plan`.
#[derive(clap::Args)]
pub struct PlanArgs {
    /// Number of sectors N (at least 1).
    #[arg(
        long,
        value_name = "N",
        required_unless_present = "sweep_sectors",
        allow_negative_numbers = true,
        value_parser = count
    )]
    pub sectors: Option<usize>,
    /// Number of harmonics N_h (at least 1).
    #[arg(long, value_name = "NH", allow_negative_numbers = true, value_parser = count)]
    pub harmonics: usize,
    /// Contact dofs per sector (at least 1).
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

fn usage(error: PlanError) -> CliError {
    let message = match error {
        PlanError::NoSectors(n) => {
            format!("--sectors {n}: the number of sectors must be at least 1")
        }
        PlanError::NoHarmonics => {
            "--harmonics 0: the number of harmonics must be at least 1".to_string()
        }
        PlanError::NoContactDofs => {
            "--contact-dofs 0: the number of contact dofs per sector must be at least 1".to_string()
        }
        PlanError::EngineOrderOutOfRange {
            engine_order,
            sectors,
            max,
        } => format!(
            "--engine-order {engine_order} is out of range: it must be in 0..={max} \
             (below --sectors {sectors})"
        ),
        PlanError::BadSweepRange { from, to } => format!(
            "--sweep-sectors {from}..{to} is not valid: it must be A..B with 1 <= A <= B <= {}",
            cyclorub_app::plan::MAX_SWEEP_SECTORS
        ),
        PlanError::Basis(e) => return CliError::failure(e.to_string()),
    };
    CliError::usage(message)
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
        let result =
            sweep(from, to, args.harmonics, excitation, args.casing_order).map_err(usage)?;
        let text = if args.json {
            to_json(&result)?
        } else {
            sweep_table(&result)
        };
        println!("{text}");
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
    base.validate().map_err(usage)?;
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
            .collect::<Result<Vec<_>, _>>()
            .map_err(usage)?;
        tables.push((rule, rows));
    }
    if args.json {
        let all: Vec<&PlanRow> = tables.iter().flat_map(|(_, rows)| rows).collect();
        println!("{}", to_json(&all)?);
    } else {
        println!(
            "{}",
            plan_tables(&base, &tables, args.engine_order.is_some())
        );
    }
    Ok(())
}

fn excitation_name(e: ExcitationKind) -> &'static str {
    match e {
        ExcitationKind::Traveling => "traveling",
        ExcitationKind::Standing => "standing",
        ExcitationKind::Mixed => "mixed (0.9 backward, 0.1 forward)",
    }
}

fn casing_name(casing: Option<usize>) -> String {
    match casing.filter(|&h| h > 0) {
        Some(h) => format!("casing of order {h}"),
        None => "circular casing".to_string(),
    }
}

fn rule_title(rule: PlanRule) -> &'static str {
    match rule {
        PlanRule::Paper => {
            "paper: traveling-wave hypothesis (Sec. 3.3) for one traveling excitation, \
             otherwise the nodal-diameter rule (Sec. 2.4) with the parity rule (Sec. 3.2.1) \
             where it applies"
        }
        PlanRule::Symmetry => {
            "symmetry: the subgroup of Z_N x Z generated by the loads' pairs (DESIGN.md §3)"
        }
    }
}

fn plan_tables(case: &PlanCase, tables: &[(PlanRule, Vec<PlanRow>)], pairs: bool) -> String {
    let mut out = String::new();
    let full = case.sectors * case.contact_dofs * (2 * case.harmonics + 1);
    let _ = writeln!(
        out,
        "N = {} sectors, N_h = {} harmonics, {} contact dof(s) per sector, {} excitation, {}",
        case.sectors,
        case.harmonics,
        case.contact_dofs,
        excitation_name(case.excitation),
        casing_name(case.casing_order)
    );
    let _ = writeln!(
        out,
        "full size: N x n x (2 N_h + 1) = {} x {} x {} = {full} unknowns",
        case.sectors,
        case.contact_dofs,
        2 * case.harmonics + 1
    );
    for (rule, rows) in tables {
        let _ = writeln!(out, "\nrule {}", rule_title(*rule));
        let _ = writeln!(
            out,
            "{:>12}  {:>10}  {:>12}  {:>18}  {:>13}  method",
            "engine order", "value of K", "reduced size", "sectors for AFT-CP", "reduction (%)"
        );
        for row in rows {
            let k = row.k.map_or("-".to_string(), |k| k.to_string());
            let _ = writeln!(
                out,
                "{:>12}  {:>10}  {:>12}  {:>18}  {:>13.1}  {}",
                row.engine_order,
                k,
                row.reduced_size,
                row.sectors_for_aft,
                row.reduction_percent,
                row.method
            );
        }
        let mean = rows.iter().map(|r| r.reduction_percent).sum::<f64>() / rows.len() as f64;
        if rows.len() > 1 {
            let _ = writeln!(out, "mean reduction over these engine orders: {mean:.1} %");
        }
        if pairs {
            for row in rows {
                let _ = writeln!(
                    out,
                    "signed nodal diameters per harmonic (engine order {}):",
                    row.engine_order
                );
                for set in &row.harmonics {
                    let list: Vec<String> = set
                        .signed_nodal_diameters
                        .iter()
                        .map(|s| s.to_string())
                        .collect();
                    let _ = writeln!(out, "  k = {:>2}: {{{}}}", set.k, list.join(", "));
                }
            }
        }
    }
    out
}

fn class_name(class: SectorClass) -> &'static str {
    match class {
        SectorClass::Even => "even N",
        SectorClass::OddNonPrime => "odd non-prime N",
        SectorClass::Prime => "prime N",
        SectorClass::All => "all N",
    }
}

fn sweep_table(result: &Sweep) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "mean reduction (%) over the non-zero engine orders, N = {}..{}, N_h = {}, {} excitation, {}",
        result.from,
        result.to,
        result.harmonics,
        excitation_name(result.excitation),
        casing_name(result.casing_order)
    );
    let _ = writeln!(
        out,
        "paper: nodal-diameter rule with / without the parity rule; symmetry: the symmetry rule"
    );
    let header = format!(
        "{:>16}  {:>5}  | h = 1..N-1: {:>7} {:>10} {:>8}  | h = 1..N/2: {:>7} {:>10} {:>8}",
        "", "count", "parity", "no parity", "symmetry", "parity", "no parity", "symmetry"
    );
    let line = |label: &str,
                count: String,
                e: &cyclorub_app::plan::MeanReductions,
                d: &cyclorub_app::plan::MeanReductions| {
        format!(
            "{:>16}  {:>5}  | {:>11} {:>7.1} {:>10.1} {:>8.1}  | {:>11} {:>7.1} {:>10.1} {:>8.1}",
            label,
            count,
            "",
            e.with_parity,
            e.without_parity,
            e.symmetry,
            "",
            d.with_parity,
            d.without_parity,
            d.symmetry
        )
    };
    let _ = writeln!(out, "{header}");
    for row in &result.rows {
        let _ = writeln!(
            out,
            "{}",
            line(
                &format!("N = {}", row.sectors),
                String::new(),
                &row.over_engine_orders,
                &row.over_nodal_diameters
            )
        );
    }
    let _ = writeln!(out, "\n{header}");
    for group in &result.groups {
        let _ = writeln!(
            out,
            "{}",
            line(
                class_name(group.class),
                group.count.to_string(),
                &group.over_engine_orders,
                &group.over_nodal_diameters
            )
        );
    }
    out
}
