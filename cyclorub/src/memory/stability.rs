//! The memory of the stability check (issue 45 item 19): its dense
//! eigenproblems, one per class being solved at once, and the address
//! space faer's matrix products reserve on each thread that solves them
//! (twice the L3 cache a thread, see [`super::matrix_product_reserve`]):
//! under `ulimit -v` that reserve, not the eigenproblems, is what made the
//! default run abort.

use super::{complexes, human, matrix_product_reserve, Budget, Refused, PRODUCT_ROWS};

/// The sizes of a stability check that its memory depends on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilitySizes {
    /// Rows of the largest dense eigenproblem of one class (`2 · dofs ·
    /// pairs`; on the whole wheel `2 · dofs · N · (2H + 1)`).
    pub rows: usize,
    /// Classes solved at once (the threads of the pool).
    pub threads: usize,
    /// Whether the check runs on a thread of its own beside the solve
    /// (`cyclorub run`'s results writer), which reserves its own workspace.
    pub own_thread: bool,
}

impl StabilitySizes {
    /// Bytes of the eigenproblems in flight: per class being solved, the
    /// Hill matrix, its eigenvectors and the Schur form's workspace (some
    /// six complex matrices of `rows²`).
    pub fn eigenproblems(&self) -> f64 {
        self.threads as f64 * complexes(6.0 * (self.rows as f64).powi(2))
    }

    /// Threads beyond the pool that multiply the check's matrices: the
    /// calling thread, and the check's own thread when it has one.
    pub fn threads_beyond_the_pool(&self) -> usize {
        1 + usize::from(self.own_thread)
    }

    /// Refuses the check, naming `stability.enabled`, when the run's other
    /// needs (`run_bytes`) fit in `without` (the budget of the run alone)
    /// but not, with the check's eigenproblems, in `with` (the budget once
    /// the check's threads have set their products' workspace aside);
    /// `reserve` is that workspace, for the message. When the run does not
    /// fit even without the check, its own check says so.
    pub fn check(
        &self,
        run_bytes: f64,
        without: &Budget,
        with: &Budget,
        reserve: f64,
    ) -> Result<(), Refused> {
        let needed = run_bytes + self.eigenproblems();
        if needed <= with.bytes || run_bytes > without.bytes {
            return Ok(());
        }
        let workspace = match self.rows > PRODUCT_ROWS {
            true => format!(
                "most of it the matrix products' workspace, {} (twice the L3 cache on each \
                 thread that solves a class)",
                human(reserve)
            ),
            false => "most of it its eigenproblems".to_string(),
        };
        Err(Refused {
            key: "stability.enabled".into(),
            value: "true".into(),
            allowed: format!(
                "the stability check of every point needs about {} more ({workspace}; \
                 its largest eigenproblem has {} rows), above the {}; \
                 turn it off (stability.enabled = false, or cyclorub run --no-stability), \
                 lower stability.harmonics, or run on fewer threads (RAYON_NUM_THREADS=1)",
                human(self.eigenproblems() + reserve),
                self.rows,
                with.source
            ),
        })
    }
}

/// Refuses a stability check that does not fit in what this process may
/// still take (see [`StabilitySizes::check`]) beside a run whose own
/// estimate is `run_bytes` and whose largest matrix has `largest_matrix`
/// rows. The products' workspace of the check's threads is set aside in
/// full: the run's budget counts the pool's and the calling thread's only
/// when its own matrices are large, and none of the check's threads has
/// multiplied a large matrix when the run starts.
pub fn check_stability(
    sizes: &StabilitySizes,
    run_bytes: f64,
    largest_matrix: usize,
) -> Result<(), Refused> {
    let without = Budget::of_this_process(largest_matrix);
    let threads = match (sizes.rows > PRODUCT_ROWS, largest_matrix > PRODUCT_ROWS) {
        (false, _) => 0,
        (true, true) => usize::from(sizes.own_thread),
        (true, false) => rayon::current_num_threads() + sizes.threads_beyond_the_pool(),
    };
    let reserve = matrix_product_reserve(threads);
    let with = Budget::of_this_process_setting_aside(largest_matrix, reserve);
    sizes.check(run_bytes, &without, &with, reserve)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn budget(bytes: f64) -> Budget {
        Budget {
            bytes,
            source: format!("{} left under the address-space limit", human(bytes)),
        }
    }

    /// The default case's check (classes of 210 rows) on the machine of
    /// the report (480 MiB of L3: 1.0 GB of products' workspace a thread),
    /// 2 threads in the pool, the calling thread and the results writer's:
    /// under `ulimit -v 2500000` the run alone fits, with the check's four
    /// workspaces it does not.
    #[test]
    fn a_check_whose_workspace_does_not_fit_is_refused_naming_stability_enabled() {
        let sizes = StabilitySizes {
            rows: 210,
            threads: 2,
            own_thread: true,
        };
        assert_eq!(sizes.threads_beyond_the_pool(), 2);
        // Six complex matrices of 210² per class, two at once: 8.5 MB.
        assert!((sizes.eigenproblems() - 2.0 * 16.0 * 6.0 * 44_100.0).abs() < 1.0);
        let per_thread = 2.0 * 480.0 * 1024.0 * 1024.0;
        let without = budget(2.3e9);
        let reserve: f64 = 4.0 * per_thread;
        let with = budget((2.3e9 - reserve).max(0.0));
        let run = 6e7;
        let error = sizes
            .check(run, &without, &with, reserve)
            .expect_err("refused")
            .to_string();
        for words in [
            "stability.enabled = true",
            "matrix products' workspace, 4.0 GB",
            "210 rows",
            "stability.enabled = false",
            "--no-stability",
            "RAYON_NUM_THREADS=1",
        ] {
            assert!(error.contains(words), "{words}: {error}");
        }
        // With room for it, the check goes on; a run that does not fit
        // alone is left to the run's own refusal.
        assert!(sizes.check(run, &without, &budget(3e9), 0.0).is_ok());
        assert!(sizes.check(3e9, &without, &with, 0.0).is_ok());
    }
}
