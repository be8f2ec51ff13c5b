//! Writes the fan sector's folder: the matrices (Matrix Market, lower
//! triangle, 17 significant digits so that a reader gets the same `f64`),
//! node coordinates, node sets, a case file and a README. Same bytes on
//! every run: nothing depends on time, paths or hash order.

use super::assembly::{AssembledMatrices, SymmetricMatrix};
use super::fan::FanMesh;
use super::readme::{case_file_name, case_text, readme_text};
use super::MeshError;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Fixed file names of a fan folder (the case file is `fan<N>.toml`).
pub const FAN_FILES: [&str; 5] = [
    "sector_mass.mtx",
    "sector_stiffness.mtx",
    "nodes.csv",
    "node_sets.toml",
    "README.md",
];

/// What [`write_fan`] wrote: each file and its size in bytes.
#[derive(Clone, Debug)]
pub struct FanOutput {
    /// Files written, in writing order, with their sizes (bytes).
    pub files: Vec<(PathBuf, u64)>,
}

/// Writes the folder `output` for the fan sector and its matrices. An
/// existing non-empty folder is refused unless `overwrite` (then only the
/// fan's own files are replaced).
pub fn write_fan(
    fan: &FanMesh,
    matrices: &AssembledMatrices,
    output: &Path,
    overwrite: bool,
) -> Result<FanOutput, MeshError> {
    prepare_folder(output, overwrite)?;
    let mut files = Vec::new();
    let mut put = |name: &str, write: &dyn Fn(&mut dyn std::io::Write) -> std::io::Result<()>| {
        let path = output.join(name);
        let io = |source| MeshError::Io {
            path: path.clone(),
            source,
        };
        let file = std::fs::File::create(&path).map_err(io)?;
        let mut out = std::io::BufWriter::with_capacity(1 << 20, file);
        write(&mut out).map_err(io)?;
        out.flush().map_err(io)?;
        let size = std::fs::metadata(&path).map_err(io)?.len();
        files.push((path, size));
        Ok::<(), MeshError>(())
    };
    put(FAN_FILES[0], &|out| {
        write_matrix_market(out, &matrices.mass, "consistent mass (kg)")
    })?;
    put(FAN_FILES[1], &|out| {
        write_matrix_market(out, &matrices.stiffness, "stiffness (N/m)")
    })?;
    put(FAN_FILES[2], &|out| {
        out.write_all(nodes_text(fan).as_bytes())
    })?;
    put(FAN_FILES[3], &|out| {
        out.write_all(node_sets_text(fan).as_bytes())
    })?;
    put(&case_file_name(fan.sectors), &|out| {
        out.write_all(case_text(fan).as_bytes())
    })?;
    put(FAN_FILES[4], &|out| {
        out.write_all(readme_text(fan, matrices).as_bytes())
    })?;
    Ok(FanOutput { files })
}

/// Creates `output` if needed; refuses a non-empty folder without `overwrite`
/// and a path that is a file.
fn prepare_folder(output: &Path, overwrite: bool) -> Result<(), MeshError> {
    let refuse = |message: String| MeshError::Output {
        path: output.to_path_buf(),
        message,
    };
    if output.exists() {
        if !output.is_dir() {
            return Err(refuse(
                "is not a folder; --output must name a folder to write the model into".into(),
            ));
        }
        let mut entries = std::fs::read_dir(output).map_err(|source| MeshError::Io {
            path: output.to_path_buf(),
            source,
        })?;
        if entries.next().is_some() && !overwrite {
            return Err(refuse(
                "the folder exists and is not empty; name another folder (--output), or replace \
                 the fan files in it (--overwrite)"
                    .into(),
            ));
        }
    }
    std::fs::create_dir_all(output).map_err(|source| MeshError::Io {
        path: output.to_path_buf(),
        source,
    })
}

/// Writes `matrix` as `coordinate real symmetric` (lower triangle, 1-based,
/// column by column, `%.16e`: 17 significant digits).
pub fn write_matrix_market(
    out: &mut dyn std::io::Write,
    matrix: &SymmetricMatrix,
    what: &str,
) -> std::io::Result<()> {
    writeln!(out, "%%MatrixMarket matrix coordinate real symmetric")?;
    writeln!(
        out,
        "% open fan sector (cyclorub mesh fan): {what}; 3 dofs per node in node order (x, y, z)"
    )?;
    writeln!(
        out,
        "{} {} {}",
        matrix.size,
        matrix.size,
        matrix.stored_entries()
    )?;
    let mut line = String::with_capacity(64);
    for (i, j, v) in matrix.entries() {
        line.clear();
        // Writing to a String cannot fail.
        let _ = writeln!(line, "{} {} {:.16e}", i + 1, j + 1, v);
        out.write_all(line.as_bytes())?;
    }
    Ok(())
}

/// `nodes.csv`: `node,x,y,z`, 1-based, metres, 17 significant digits.
pub fn nodes_text(fan: &FanMesh) -> String {
    let mut text = String::from("node,x,y,z\n");
    for (n, [x, y, z]) in fan.mesh.nodes.iter().enumerate() {
        let _ = writeln!(text, "{},{x:.16e},{y:.16e},{z:.16e}", n + 1);
    }
    text
}

/// `node_sets.toml`: the node sets, 1-based.
pub fn node_sets_text(fan: &FanMesh) -> String {
    let list = |nodes: &[usize]| {
        let items: Vec<String> = nodes.iter().map(|n| (n + 1).to_string()).collect();
        let mut text = String::from("[");
        for (k, chunk) in items.chunks(16).enumerate() {
            let _ = write!(
                text,
                "{}\n    {}",
                if k == 0 { "" } else { "," },
                chunk.join(", ")
            );
        }
        text.push_str(",\n]");
        text
    };
    let s = &fan.sets;
    let mut text = String::new();
    text.push_str(
        "# Node sets of the open fan sector (cyclorub mesh fan); 1-based node numbers of\n\
         # nodes.csv; dofs are 3 per node in node order (x, y, z).\n\n",
    );
    let _ = writeln!(
        text,
        "# The bore face r = {} m: every dof fixed.\nclamped = {}\n",
        fan.geometry.bore_radius,
        list(&s.clamped)
    );
    let _ = writeln!(
        text,
        "# The θ = −π/N face; paired in order with right_boundary.\nleft_boundary = {}\n",
        list(&s.left_boundary)
    );
    let _ = writeln!(
        text,
        "# The θ = +π/N face: right_boundary[i] is left_boundary[i] rotated by 2π/N about z.\n\
         right_boundary = {}\n",
        list(&s.right_boundary)
    );
    let _ = writeln!(
        text,
        "# Nine nodes evenly spaced along the blade tip's pressure-side edge (t = −thickness/2),\n\
         # leading edge (z < 0) first.\ncontact = {}\n",
        list(&s.contact)
    );
    let _ = writeln!(
        text,
        "# The blade tip at mid-chord, mid-thickness (θ = 0: its y dof is circumferential).\n\
         excitation = [{}]\n",
        s.excitation + 1
    );
    let _ = writeln!(
        text,
        "# Mid-chord, mid-thickness at three quarters of the span (θ = 0): bending moves it a\n\
         # lot, away from the contact edge.\nobservation = [{}]\n",
        s.observation + 1
    );
    let _ = writeln!(
        text,
        "# Every blade node above the root section (the root is the disk's top face):\n\
         # [mistuning] scales the stiffness entries between two of them.\nblade = {}",
        list(&s.blade)
    );
    text
}
