//! `rollphase sweep SPEC.toml`: a parameter scan of 3D rolling, one CSV row per run.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use crate::figures::shard::ShardSpec;
use crate::figures::sweep;
use crate::figures::sweep::SweepRan;

/// Scan bodies × α × m/m0 × initial orientations × integrators in 3D, one CSV row per run:
/// its fate (halted, periodic, left_model, undecided), period T, 1/T, period multiplicity, when it halted,
/// and the RHS evaluations it took. Writes OUT/sweep.csv and OUT/summary.json.
///
/// Answers do not depend on the integrator: a fate found with a setting coarser than DOP853 at
/// rtol 1e-10 is re-decided by that reference before it is written (a cycle from its last
/// crossing, a few periods; a halt or an undecided run from the start). The column
/// answer_check says "confirmed" or "corrected" (fast_fate, fast_period, fast_multiplicity then
/// hold what the fast setting said), or "reference" for a setting at least that precise.
///
/// The spec (TOML: plain keys first, then the [bodies] table; paths relative to its folder):
///   alpha = [0.12, 0.15]         # or { from = 0.1, to = 0.2, count = 11 }
///   mass_ratio = [0.0, 6.0]      # 0 = viscous; same forms [default: 0]
///   orientations = 20            # random releases from rest per point [default: 1]
///   orientation_seed = 1
///   integrators = ["balanced"]   # fast | balanced | precise | dop853:RTOL | rk4:DT | cf4:DT
///   t_max = 2000.0               # longest run; max_multiplicity = 4, point_tol = period_rtol = 1e-5
///
///   [bodies]
///   paper_seeds = [219]          # the paper authors' numpy bodies
///   seeds = [1, 2, 3]            # our random bodies (non-convex ones are skipped)
///   files = ["body.json"]        # shape files
///   sigma = 0.25                 # of generated bodies; max_degree = 5
///
/// --shard I/N runs only shard I of N and writes OUT/shard-I-of-N.json; `rollphase merge OUT`
/// then writes sweep.csv, byte for byte what one unsharded run writes (docs/guide/cluster.md).
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct SweepArgs {
    /// The sweep spec (TOML).
    pub spec: PathBuf,
    /// Output folder.
    #[arg(long, default_value = "sweep")]
    pub out: PathBuf,
    /// Run only shard I of N (1-based), e.g. 3/8.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<ShardSpec>,
    /// Worker threads [default: all cores].
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Runs `sweep`.
pub fn run(a: SweepArgs) -> Result<()> {
    let pool = super::figure::thread_pool(a.threads)?;
    match pool.install(|| sweep::run(&a.spec, &a.out, a.shard))? {
        SweepRan::Whole(s) => outln!(
            "sweep: {} runs ({} halted, {} periodic, {} left the model, {} undecided; {} cruise; \
             {} corrected by the reference){}; wrote {}",
            s.runs,
            s.halts,
            s.periodic,
            s.left_model,
            s.undecided,
            s.cruising,
            s.corrected,
            if s.skipped_not_convex.is_empty() {
                String::new()
            } else {
                format!("; skipped {} non-convex bodies", s.skipped_not_convex.len())
            },
            a.out.join("sweep.csv").display()
        ),
        SweepRan::Shard(w) => outln!("sweep: {w}; {}", w.next_step(&a.out)),
    }
}
