//! `cyclorub mesh fan [--sectors 16] [--refine R] --output DIR [--overwrite]`:
//! writes the open fan sector's model files and its case file, which
//! `cyclorub run` reads (`kind = "finite_element"`: Craig–Bampton per
//! nodal diameter).

use super::{outln, CliError};
use cyclorub::mesh::{assemble, fan, write_fan, FanGeometry, DEFAULT_REFINE, MAX_REFINE};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `cyclorub mesh`.
#[derive(clap::Args)]
pub struct MeshArgs {
    #[command(subcommand)]
    kind: MeshKind,
}

#[derive(clap::Subcommand)]
enum MeshKind {
    /// An open fan-stage sector (titanium disk sector and a twisted blade
    /// of constant thickness, 20-node hexahedra): matrices, node
    /// coordinates, node sets, a case file and a README.
    Fan(FanArgs),
}

/// Arguments of `cyclorub mesh fan`.
#[derive(clap::Args)]
pub struct FanArgs {
    /// Number of sectors of the wheel (3 to 23 for this blade).
    #[arg(long, default_value_t = 16, allow_hyphen_values = true)]
    sectors: usize,
    /// Mesh refinement: 1 is coarse (1,287 dofs, for tests), 3 the default
    /// (17,379 dofs); at most 8.
    #[arg(long, default_value_t = DEFAULT_REFINE, allow_hyphen_values = true)]
    refine: usize,
    /// Folder to write into (created if needed).
    #[arg(long)]
    output: PathBuf,
    /// Write into an existing non-empty folder, replacing the fan's files.
    #[arg(long)]
    overwrite: bool,
}

/// Runs `cyclorub mesh`.
pub fn execute(args: MeshArgs) -> Result<(), CliError> {
    match args.kind {
        MeshKind::Fan(args) => execute_fan(args),
    }
}

fn execute_fan(args: FanArgs) -> Result<(), CliError> {
    if args.refine == 0 || args.refine > MAX_REFINE {
        return Err(CliError::usage(format!(
            "--refine {}: allowed 1 (coarse) to {MAX_REFINE}; the default is {DEFAULT_REFINE}",
            args.refine
        )));
    }
    let started = Instant::now();
    let fan = fan(args.sectors, args.refine, &FanGeometry::default())?;
    let matrices = assemble(&fan.mesh)?;
    let built = started.elapsed();
    let output = write_fan(&fan, &matrices, &args.output, args.overwrite)?;
    let total = started.elapsed();
    outln!(
        "open fan sector, {} sectors, refine {}: {} nodes, {} dofs; {} disk + {} blade elements \
         (20-node hexahedra)",
        fan.sectors,
        fan.refine,
        fan.mesh.nodes.len(),
        fan.dofs(),
        fan.disk_elements(),
        fan.blade_elements()
    );
    outln!(
        "node sets: {} clamped, {} + {} cyclic boundary, {} contact, excitation node {}, \
         observation node {}",
        fan.sets.clamped.len(),
        fan.sets.left_boundary.len(),
        fan.sets.right_boundary.len(),
        fan.sets.contact.len(),
        fan.sets.excitation + 1,
        fan.sets.observation + 1
    );
    outln!(
        "stored entries (lower triangle): mass {}, stiffness {}",
        matrices.mass.stored_entries(),
        matrices.stiffness.stored_entries()
    );
    for (path, size) in &output.files {
        outln!("wrote {} ({})", path.display(), human(*size));
    }
    outln!(
        "meshed and assembled in {:.2} s, written in {:.2} s; run the case with cyclorub run \
         (the first run reduces the sector and caches it in .cyclorub-cache)",
        built.as_secs_f64(),
        (total - built).as_secs_f64()
    );
    Ok(())
}

/// A byte count for people.
fn human(bytes: u64) -> String {
    match bytes {
        b if b >= 1 << 20 => format!("{:.1} MiB", b as f64 / (1u64 << 20) as f64),
        b if b >= 1 << 10 => format!("{:.1} KiB", b as f64 / (1u64 << 10) as f64),
        b => format!("{b} bytes"),
    }
}
