//! `rollphase shape`: a seeded random body written as a shape file.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;

use crate::geometry::{Body, paper_disk, paper_sphere, random_disk, random_sphere};

/// Generate a random body and write its shape file.
///
/// 2D (a cylinder's cross-section): r(θ) = 1 + Σ_{l=2..M} A_l/l² sin(l(θ − θ_l)),
/// A_l ~ N(0, σ), θ_l ~ U[0, 2π). The paper uses σ = 0.08, M = 10 (viscous) and σ = 0.12, M = 5
/// (inertial). 3D: r = 1 + Re Σ_{l=2..L} Σ_m A_lm/(l(l+1)) Y_l^m, A_lm = a·e^{imP} with
/// a ~ N(0, σ), P ~ U[0, 2π); the paper uses σ = 0.25, L = 5. The same seed always gives the
/// same body. A body that is not strictly convex is refused (try another seed or a smaller σ).
///
/// --paper-seed N instead reproduces the paper authors' own bodies bit for bit (their code draws
/// with numpy: np.random.seed(N), all amplitudes, then all phases). The body of the paper's
/// Figs. 3–4 is
///   rollphase shape --dim 3 --paper-seed 219 --sigma 0.25 --modes 5 -o paper-sphere.json
/// (bundled as assets/shapes/paper-sphere.json).
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct ShapeArgs {
    /// 2 for a disk (cylinder), 3 for a sphere.
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..=3))]
    pub dim: u32,
    /// Random seed (rollphase's own generator).
    #[arg(
        long,
        required_unless_present = "paper_seed",
        conflicts_with = "paper_seed"
    )]
    pub seed: Option<u64>,
    /// numpy seed (0..=4294967295) of the paper authors' generator: the same body as their code.
    #[arg(long)]
    pub paper_seed: Option<u32>,
    /// Standard deviation σ of the amplitudes [default: 0.08 in 2D, 0.25 in 3D].
    #[arg(long, allow_negative_numbers = true)]
    pub sigma: Option<f64>,
    /// Highest degree l of the modes: M in 2D (2..=64), L in 3D (2..=12) [default: 10 in 2D, 5
    /// in 3D]. The paper authors' 2D generator counts modes instead: their get_r(seed,
    /// num_modes, std) covers l = 2 … num_modes + 1, so their num_modes = 8 is --modes 9 here.
    /// In 3D their L is this L (seed 219, l ≤ 5: --modes 5).
    #[arg(long)]
    pub modes: Option<u32>,
    /// Output file [default: standard output].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

/// Runs `shape`.
pub fn run(a: ShapeArgs) -> Result<()> {
    let (sigma, modes) = if a.dim == 2 {
        (a.sigma.unwrap_or(0.08), a.modes.unwrap_or(10))
    } else {
        (a.sigma.unwrap_or(0.25), a.modes.unwrap_or(5))
    };
    let (body, which) = match (a.paper_seed, a.seed) {
        (Some(n), _) if a.dim == 2 => (Body::Disk(paper_disk(n, sigma, modes)?), "paper seed"),
        (Some(n), _) => (Body::Sphere(paper_sphere(n, sigma, modes)?), "paper seed"),
        (None, Some(n)) if a.dim == 2 => (Body::Disk(random_disk(n, sigma, modes)?), "seed"),
        (None, Some(n)) => (Body::Sphere(random_sphere(n, sigma, modes)?), "seed"),
        (None, None) => bail!("give --seed N or --paper-seed N"),
    };
    if let Err(e) = body.check_rollable() {
        let n = a.paper_seed.map_or_else(|| a.seed.unwrap_or(0), u64::from);
        bail!("{which} {n} gives a body the models cannot roll: {e}");
    }
    if let (Body::Disk(d), Err(_)) = (&body, body.check_convex()) {
        let bridges = d.hull().bridges();
        let deepest = bridges.iter().map(|b| b.depth).fold(0.0, f64::max);
        eprintln!(
            "note: this body is not convex: it has {} dent(s), the deepest {deepest:.4} ⟨r⟩ under \
             the flat that spans it; `simulate` rolls it on its convex hull (across a dent on the \
             flat, tipping from one end to the other), the other commands refuse it",
            bridges.len()
        );
    }
    super::write_output(
        a.output.as_ref(),
        &(body.to_shape().to_json()? + "\n"),
        &crate::output::Inputs::none(),
    )
}
