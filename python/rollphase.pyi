"""Irregular cylinders and spheres rolling down a ramp (Qian, Jung & Mahadevan, PNAS 2025).

Units: the force F, the drag γ and the mean radius ⟨r⟩ are 1; angles are in radians; mass is
m/m0 (0: the viscous model). Orientations are body-to-lab unit quaternions (w, x, y, z); the
ramp frame has x downhill and z along the ramp's normal.

Arguments: the body and the ramp angle (and simulate's t_end) by position, every setting by
name. Errors: bad input raises InputError (a ValueError) with the command line's message, a run
that fails RunError (a RuntimeError), all of them RollphaseError; Ctrl-C stops a long call with
KeyboardInterrupt. The dicts the studies return are typed below (TypedDicts, for type checkers
only: import them under typing.TYPE_CHECKING).
"""

from os import PathLike
from typing import Any, List, Literal, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt
from typing_extensions import NotRequired

__version__: str

_Path = Union[str, PathLike]
_Floats = npt.ArrayLike
_Array = npt.NDArray[np.float64]
_Complex = npt.NDArray[np.complex128]

class RollphaseError(Exception):
    """Base of every error rollphase raises."""

class InputError(RollphaseError, ValueError):
    """Bad input, refused before any work; also a ValueError."""

class RunError(RollphaseError, RuntimeError):
    """A run that started and could not finish (step budget spent, step too small, state no
    longer finite, fixed step too coarse); also a RuntimeError."""

class LeftModelError(RunError):
    """A run stopped where the rolling model stops holding (on_invalid="stop")."""

class InternalError(RollphaseError, RuntimeError):
    """A bug in rollphase (a worker panicked). Please report it."""

class RunSummary(TypedDict):
    """A run's summary: the command line's --summary keys, plus one float per drag-law
    parameter (the keys of drag_parameters())."""

    model: str
    integrator: str
    rhs_evals: int
    steps: int
    rejected: int
    max_quat_norm_error: Optional[float]
    max_contact_normal_error: Optional[float]
    energy_drift: Optional[float]
    t_end: float
    model_note: Optional[str]
    min_normal_force: float
    max_normal_force: float
    max_friction_needed: Optional[float]
    lift_off_t: Optional[float]
    slip_t: Optional[float]
    friction: Optional[float]
    wall_seconds: float
    rhs_evals_per_second: float
    alpha: float
    mass_ratio: float
    tips: NotRequired[int]
    tip_energy_lost: NotRequired[float]
    rested_t: NotRequired[Optional[float]]
    fate: str
    """The verdict's word: "left_model", "halted" or "undecided" (a fixed-time run does not
    look for a cycle)."""
    t: NotRequired[Optional[float]]
    """With "halted": at rest from this time on."""
    violation: NotRequired[dict[str, Any]]
    """With "left_model": the first violation (`kind` "lift_off" or "slip", `t`)."""
    why: NotRequired[dict[str, Any]]
    """With "undecided": `reason` and what it measured."""

class DegreeResidual(TypedDict):
    modes: int
    rms: float

class CoatReport(TypedDict):
    """MeshFitReport["coat"]: what a coat of uniform thickness did (Body.from_mesh(coat_mm=))."""

    coat_mm: float
    scale_mm_before: float
    scale_mm_after: float
    alpha_star_before: float
    alpha_star_after: float

class SectionHull(TypedDict):
    """MeshFitReport["mesh_hull"] (2D): the section's own convex hull, as printed."""

    sides: int
    alpha_star: float
    longest_side: float

class SolidHull(TypedDict):
    """MeshFitReport["solid_hull"] (3D): the mesh's own convex hull, as printed."""
    vertices: int
    triangles: int
    alpha_star: float
    longest_edge: float

class MeshFitReport(TypedDict):
    """Body.mesh_fit: the fit of a body to a mesh, as `rollphase shape --from-mesh --report`."""

    file: str
    format: str
    triangles: int
    dimension: int
    modes: int
    modes_rule: str
    scale_mm: float
    scale_mm_error: Optional[float]
    size_mm: float
    centroid: List[float]
    axis: Optional[List[float]]
    section_axes: Optional[List[List[float]]]
    rms_residual: float
    rms_residual_mm: float
    max_residual: float
    max_residual_mm: float
    max_residual_at: str
    l1_part: float
    l1_offset_mm: float
    degree_residuals: List[DegreeResidual]
    convex: bool
    alpha_star: float
    alpha_star_error: Optional[float]
    alpha_star_bias: Optional[float]
    error_blocks: Optional[int]
    mesh_hull: Optional[SectionHull]
    solid_hull: Optional[SolidHull]
    warnings: List[str]
    coat: NotRequired[CoatReport]

class CruisingFraction(TypedDict):
    cruising: int
    halted: int
    undecided: int
    fraction: float

class PeriodicOrbit(TypedDict):
    point: _Array
    omega: _Array
    period: float
    multipliers: _Complex
    max_modulus: float
    stable: bool
    starts: int
    newton_steps: int

class PredictedOrbit(TypedDict):
    period: float
    repeat: int
    advance_down: float
    advance_across: float
    advance_down_mm: Optional[float]
    advance_across_mm: Optional[float]
    speed: float
    stable: bool
    stability: str
    members: int
    min_normal_force: Optional[float]
    lift_off_t: Optional[float]
    multipliers: _Complex
    max_modulus: float
    fraction: float
    starts: int
    crossing: _Array
    omega: _Array
    path: _Array

class UndecidedShare(TypedDict):
    reason: str
    fraction: float
    what_would_decide: str

class Violation(TypedDict):
    kind: str
    t: float

class Fates(TypedDict):
    """How the starts ended, as fractions of all starts: the one verdict's words."""
    periodic: float
    neutral: float
    halted: float
    left_model: float
    undecided: float
    undecided_reasons: List[UndecidedShare]
    first_violation: Optional[Violation]

class Prediction(TypedDict):
    """predict's answer; it also holds one float per drag-law parameter (the keys of
    drag_parameters())."""

    model: str
    dimension: int
    alpha: float
    mass_ratio: float
    alpha_star: float
    starts: int
    halts: float
    undecided: float
    fates: Fates
    scale_mm: Optional[float]
    orbits: List[PredictedOrbit]

class Significance(TypedDict):
    """The check against chance: surrogate tracks with the track's smoothed spectrum."""
    surrogates: int
    surrogate_floor: float
    normalised_dip: float
    p_bound: float

class MarkerReading(TypedDict):
    """Whether the markers repeat after one period or only after two, with the evidence."""
    verdict: Literal["every_period", "every_other_period", "no_repeat", "too_sparse"]
    detections: int
    cycles: int
    pairs_one: int
    pairs_two: int
    mismatch_one_cm: float
    mismatch_two_cm: float
    chance_floor_cm: float
    score: float
    shuffled_score_max: float
    shuffles: int
    reason: str

class BlockCheck(TypedDict):
    """TrackMeasurement["block_check"]: the harmonic fit on blocks of the track."""

    blocks: int
    reduced_chi2: Optional[float]
    threshold: float
    turns_vary: bool
    residual_ratio: float

class TurnRule(TypedDict):
    """Whether a track's turns follow from one another by a rule (a chaotic motion, which gets
    no period) or swing with a second period (a quasi-periodic one, which gets none either): the
    turns read, the analogues' error over a straight line's (about 2 for turns that vary by
    chance, under 0.25 for a rule; None under 20 turns, or where the frame grid or a repeat
    after a few turns explains the peaks), the peaks before it predicts from, the second period
    in turns (None without one) and whether the frame grid explains the peaks."""

    turns: int
    ratio: Optional[float]
    lags: int
    second_period_turns: Optional[float]
    frame_grid: bool

class RepeatShown(TypedDict):
    """TrackMeasurement["repeat_shown"]: how closely the period is shown to be the motion's."""

    shown: Literal["closely", "by_markers", "roughly"]
    beyond_noise: Optional[float]
    after: NotRequired[int]
    turn_rule: NotRequired[Optional[TurnRule]]
    caveat: str

class TrackMeasurement(TypedDict):
    period_frames: float
    period_error_frames: float
    period_error_from: Literal["harmonics", "cycles", "dip_width"]
    period_spread_frames: Optional[float]
    cycle_periods: _Array
    unrepeated_cycles: int
    periods_seen: int
    mismatch: float
    advance_down: float
    advance_across: float
    advance_error: Optional[List[float]]
    velocity: Optional[List[List[float]]]
    significance: Optional[Significance]
    block_check: Optional[BlockCheck]
    mismatch_curve: _Array
    frames_used: List[float]
    folded: _Array
    warnings: List[str]
    turn_rule: Optional[TurnRule]
    marker_reading: NotRequired[MarkerReading]
    repeat_shown: RepeatShown

class ModelComparison(TypedDict):
    alpha: float
    scale_mm: float
    mass_ratio_model: float
    mass_ratio: float
    mass_ratio_from: Literal["period", "given", "viscous_period"]
    t0_s: float
    mass_ratio_from_speed: float
    t0_from_speed_s: float
    period_from_speed_s: float
    predicted_period_t0: float
    predicted_period_s: float
    predicted_advance_down_cm: float
    predicted_advance_across_cm: float
    predicted_speed_cm_s: float
    advance_down_difference: float
    period_difference: float
    speed_difference: float
    repeat: int
    orbit_fraction: float
    orbits: List[List[float]]
    iterations: int
    period_sensitivity: Optional[float]
    mass_ratio_error: Optional[float]
    t0_error_s: Optional[float]
    path: _Array
    phase: NotRequired[int]
    mirrored_across: NotRequired[bool]
    handedness_shown: NotRequired[bool]
    down_explained: NotRequired[float]
    across_explained: NotRequired[List[float]]

class PeriodCounts(TypedDict):
    cycle_counts: npt.NDArray[np.uint64]
    at_rest: int
    undecided: int
    left_model: int
    longest_run: float

class ContinuedOrbit(TypedDict):
    orbit: int
    mass_ratio: _Array
    period: _Array
    most_negative_real: _Array
    multipliers: _Complex

class Flip(TypedDict):
    orbit: int
    mass_ratio: float
    loses_stability: bool

class PeriodTwoWindow(TypedDict):
    orbit: int
    onset_mass: float
    end_mass: Optional[float]
    flip_onset_mass: Optional[float]
    flip_end_mass: Optional[float]

class MassBifurcation(TypedDict):
    masses: _Array
    period_counts: npt.NDArray[np.uint64]
    orbits: List[ContinuedOrbit]
    flips: List[Flip]
    windows: List[PeriodTwoWindow]
    undecided_runs: int
    longest_run: float

class Body:
    """A rolling body: a disk (2D, r(θ) = 1 + Σ a_l/l² sin(l(θ − θ_l))) or a sphere (3D,
    r(u) = 1 + Re Σ A_lm/(l(l+1)) Y_lm(u)), with mean radius 1."""

    @staticmethod
    def paper_sphere(seed: int, *, sigma: float = 0.25, modes: int = 5) -> Body:
        """The paper's 3D body for a numpy seed (the authors' generator, bit for bit); seed 219
        is the body of the paper's Figs. 3 and 4. modes is the highest degree l, as the
        authors' L."""
    @staticmethod
    def paper_disk(seed: int, *, sigma: float = 0.08, modes: int = 10) -> Body:
        """The paper's 2D body for a numpy seed (the authors' generator, bit for bit). modes is the
        highest degree l; the authors' get_r(seed, num_modes, std) covers l = 2 … num_modes + 1,
        so their num_modes = 8 is modes=9 here."""
    @staticmethod
    def random_sphere(seed: int, *, sigma: float = 0.25, modes: int = 5) -> Body:
        """A random sphere from rollphase's own seeded generator."""
    @staticmethod
    def random_disk(seed: int, *, sigma: float = 0.08, modes: int = 10) -> Body:
        """A random disk from rollphase's own seeded generator."""
    @staticmethod
    def from_file(path: _Path) -> Body:
        """A body from a shape file (JSON, as `rollphase shape` writes)."""
    @staticmethod
    def from_mesh(
        path: _Path,
        *,
        modes: Optional[int] = None,
        dim: Optional[int] = None,
        axis: Optional[Tuple[float, float, float]] = None,
        mm_per_unit: float = 1.0,
        coat_mm: Optional[float] = None,
        ignore_facets: bool = False,
    ) -> Body:
        """A body fitted to a printed or scanned mesh (.stl, .obj, .ply; mm unless mm_per_unit
        says otherwise), as `rollphase shape --from-mesh` fits it: 3D by real spherical harmonics
        about the volume centroid, 2D (an extruded cylinder, found or dim=2) by a Fourier
        series of its section. The report is body.mesh_fit; warnings are UserWarnings; a mesh
        that is open, not star-shaped about its centroid, or fits no convex body raises
        InputError naming the place. coat_mm coats the fitted body with that many mm of uniform
        thickness and fits it again (mesh_fit["coat"]: ⟨r⟩ and α* before and after)."""
    def to_file(self, path: _Path) -> None:
        """Writes the body as a shape file, whole or not at all (a link stays a link)."""
    def to_json(self) -> str:
        """The shape file's JSON text."""
    @property
    def alpha_star(self) -> float:
        """The critical angle α* = atan max |∇ ln r| (rad)."""
    @property
    def dimension(self) -> int:
        """2 for a disk, 3 for a sphere."""
    @property
    def scale_mm(self) -> Optional[float]:
        """Millimetres per mean radius of the real object (a fitted body, or a shape file with
        scale_mm); None otherwise."""
    @property
    def mesh_fit(self) -> Optional[MeshFitReport]:
        """The mesh fit's report for a body from Body.from_mesh: rms_residual(_mm),
        max_residual(_mm), max_residual_at, l1_part, l1_offset_mm, scale_mm, modes, modes_rule,
        degree_residuals, convex, alpha_star, warnings, …; None otherwise."""
    @property
    def is_convex(self) -> bool:
        """Whether the body is convex (runs refuse a non-convex body)."""
    def radius(self, points: _Floats) -> npt.NDArray[np.float64]:
        """Disk: r(θ) at each angle (any shape, the same shape back). Sphere: r(u) at each
        direction of an (N, 3) array (normalised; N radii back) or of one (3,) direction."""

class Trajectory:
    """What every run's samples have: t (S,) and the ramp's force on the body in units of the
    weight F, normal_force (S,), friction (S, 2) (x downhill, y across) and friction_needed
    (S,) = |friction|/normal_force (inf where normal_force ≤ 0); from simulate_many each but t
    with a leading axis of one row per start. The base of DiskTrajectory, SphereTrajectory and
    SphereRuns."""

    @property
    def t(self) -> _Array: ...
    @property
    def normal_force(self) -> _Array: ...
    @property
    def friction(self) -> _Array: ...
    @property
    def friction_needed(self) -> _Array: ...
    @property
    def dimension(self) -> Literal[2, 3]: ...
    @property
    def columns(self) -> List[str]: ...
    def __len__(self) -> int: ...

class DiskTrajectory(Trajectory):
    """One disk's run: theta (contact angle in the body), theta_dot, psi (the body's rotation),
    x (downhill), y (height), each (S,)."""

    @property
    def theta(self) -> _Array: ...
    @property
    def theta_dot(self) -> _Array: ...
    @property
    def psi(self) -> _Array: ...
    @property
    def x(self) -> _Array: ...
    @property
    def y(self) -> _Array: ...
    @property
    def summary(self) -> RunSummary: ...

class SphereTrajectory(Trajectory):
    """One sphere's run: q (S, 4) w, x, y, z, contact (S, 3) body-frame contact point, omega
    (S, 3) lab angular velocity, com (S, 3) centre of mass."""

    @property
    def q(self) -> _Array: ...
    @property
    def contact(self) -> _Array: ...
    @property
    def omega(self) -> _Array: ...
    @property
    def com(self) -> _Array: ...
    @property
    def summary(self) -> RunSummary: ...

class SphereRuns(Trajectory):
    """simulate_many's runs, one row per start: q (N, S, 4), contact, omega, com (N, S, 3),
    and one summary per start."""

    @property
    def q(self) -> _Array: ...
    @property
    def contact(self) -> _Array: ...
    @property
    def omega(self) -> _Array: ...
    @property
    def com(self) -> _Array: ...
    @property
    def summaries(self) -> List[RunSummary]: ...

_Integrator = Literal["dop853", "rk4", "cf4"]
_OnInvalid = Literal["warn", "stop"]

def simulate(
    body: Body,
    alpha: float,
    t_end: float,
    *,
    mass_ratio: float = 0.0,
    q0: Optional[Sequence[float]] = None,
    contact: Optional[Sequence[float]] = None,
    spin: Optional[float] = None,
    omega0: Optional[Sequence[float]] = None,
    theta0: Optional[float] = None,
    theta_dot0: Optional[float] = None,
    integrator: _Integrator = "dop853",
    rtol: float = 1e-10,
    atol: Optional[float] = None,
    dt: float = 0.01,
    samples: int = 1001,
    drag: float = 1.0,
    max_steps: int = 100_000_000,
    friction: Optional[float] = None,
    on_invalid: _OnInvalid = "warn",
    **drag_law: float,
) -> Union[DiskTrajectory, SphereTrajectory]:
    """One run on a ramp at angle alpha (rad) from t = 0 to t_end, as `rollphase simulate`
    (the same numbers to the last digit). mass_ratio 0 is viscous, > 0 inertial. Sphere start:
    q0 (w, x, y, z) or contact (θ, φ) turned by spin; omega0 for inertial runs. Disk start:
    theta0, theta_dot0. integrator: "dop853" (rtol, atol), "rk4" or "cf4" (dt).
    friction: the surface's μ (slip is checked against it); on_invalid: "warn" (a
    RuntimeWarning when the body leaves the ramp or slips) or "stop" (LeftModelError there).
    A disk's run is a DiskTrajectory, a sphere's a SphereTrajectory. Further keywords are
    the drag law's parameters by their keys (drag_parameters() lists them)."""

def simulate_many(
    body: Body,
    alpha: float,
    t_end: float,
    *,
    q0s: _Floats,
    mass_ratio: float = 0.0,
    omega0: Optional[Sequence[float]] = None,
    integrator: _Integrator = "dop853",
    rtol: float = 1e-10,
    atol: Optional[float] = None,
    dt: float = 0.01,
    samples: int = 1001,
    drag: float = 1.0,
    max_steps: int = 100_000_000,
    friction: Optional[float] = None,
    on_invalid: _OnInvalid = "warn",
    **drag_law: float,
) -> SphereRuns:
    """A sphere from each quaternion of the (N, 4) array q0s, in parallel with the GIL
    released; arrays stacked: q (N, S, 4), contact, omega, com (N, S, 3), t (S,)."""

def critical_angle(body: Body) -> float:
    """α* = atan max |∇ ln r| (rad), as body.alpha_star."""

def period(
    body: Body,
    alpha: float,
    *,
    mass_ratio: float = 0.0,
    theta0: float = 0.0,
    theta_dot0: float = 0.0,
    t_max: float = 5000.0,
    rtol: float = 1e-10,
    **drag_law: float,
) -> Optional[float]:
    """A disk's period T (time for θ to advance 2π), None when it halts, nan (with a
    RuntimeWarning saying what would decide it) when undecided: not measurable, or still
    changing at t_max (a transient is never returned as T), or within a few ulps of α*; as
    `rollphase period`. What the command line says beside a number is a RuntimeWarning here: a
    T known to less than 1e-9 (within about 1e-8 of α*: how well it is known), the viscous limit
    taken (mass_ratio ≤ rtol), a stiff run's cost. Further keywords are drag-law parameters
    (drag_parameters())."""

def poincare_map(
    body: Body,
    alpha: float,
    *,
    starts: _Floats,
    t_max: float = 2000.0,
    rtol: float = 1e-10,
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The viscous Poincaré map on ∂Ω: from an (N, 4) array of quaternions with w = 0, the
    next crossings (N, 4) and return times (N,); nan where the body halts or t_max passes."""

def cruising_fraction(
    body: Body, alpha: float, *, orientations: int = 1000, seed: int = 1
) -> CruisingFraction:
    """Fig. 3b: of random orientations released from rest (viscous), how many cruise. Keys:
    cruising, halted, undecided, fraction."""

def periodic_orbits(
    body: Body,
    alpha: float,
    *,
    mass_ratio: float = 0.0,
    orientations: int = 64,
    seed: int = 1,
    t_min: float = 2000.0,
    t_cap: float = 20000.0,
    tol: float = 1e-5,
) -> List[PeriodicOrbit]:
    """The period-1 orbits random starts settle on, each a fixed point of the return map on ∂Ω
    with its Floquet multipliers. Keys: point, omega, period, multipliers (complex),
    max_modulus, stable, starts, newton_steps."""

def predict(
    body: Body,
    alpha: float,
    *,
    mass_ratio: float = 0.0,
    starts: int = 32,
    seed: int = 1,
    t_cap: float = 20000.0,
    **drag_law: float,
) -> Prediction:
    """The stable periodic motions runs from rest settle into, as `rollphase predict` gives them.
    Keys: alpha, mass_ratio, alpha_star, starts, halts, undecided, fates (every start's fate:
    periodic, neutral, halted, left_model, undecided, with the reasons), scale_mm, and orbits
    (most visited first), each with period, repeat (1 or 2), advance_down, advance_across (per
    repeat, in mean radii), advance_down_mm, advance_across_mm (None without a scale), speed,
    stable, stability ("stable", "neutral", "unstable"), members, min_normal_force and
    lift_off_t (inertial), multipliers (complex), max_modulus, fraction, starts, crossing, omega, and path
    (an (N, 2) array of the centre over three repeats)."""

class DragParameter(TypedDict):
    """One registered drag-law parameter."""

    key: str
    help: str
    default: float
    min: float
    max: float

def drag_parameters() -> List[DragParameter]:
    """The drag-law parameters simulate, simulate_many, period and predict take as keywords,
    each with its key, what it means, its default (the paper's linear drag) and its range."""

class ModelInfo(TypedDict):
    """One registered rolling model."""

    name: str
    dimension: int
    inertial: bool
    about: str
    state: List[str]

def models() -> List[ModelInfo]:
    """The rolling models there are (the core's registry): each with the name summaries, CSV
    and the command line use, the body's dimension, whether it carries inertia, what it is and
    its integrated state. A run's model follows from the body and mass_ratio (0: viscous)."""

class ReplayCheck(TypedDict):
    """What replay() reached against the saved state, as `rollphase replay` checks it."""

    to_the_bit: bool
    entries: int
    saved_t: float
    reached_t: float
    saved_model: str
    reached_model: str
    numbers: int
    differing: int
    worst: float
    state: npt.NDArray[np.float64]
    bodies_not_replayed: int

def replay(state: _Path) -> ReplayCheck:
    """A saved state of the app (a scene with [resume] and [[replay]]) run again from its scene's
    start through its [[replay]] and the lesson's steps, as `rollphase replay STATE`: whether it
    reaches the saved state to the bit, and by how much it misses. The replay is the scene's own
    body's: bodies_not_replayed counts the other bodies ([[bodies]]), whose saved states are
    loaded as written. A scene that is not a saved state raises InputError."""

class TrackTable(TypedDict):
    format: Literal["plain", "tracker", "trackpy"]
    columns: List[str]
    frames: npt.NDArray[np.float64]
    across: npt.NDArray[np.float64]
    down: npt.NDArray[np.float64]
    fps_from_times: Optional[float]
    time_origin: Optional[float]
    notes: List[str]

def read_track_table(
    path: _Path,
    *,
    format: Optional[Literal["plain", "tracker", "trackpy"]] = None,
    frame_column: Optional[str] = None,
    time_column: Optional[str] = None,
    across_column: Optional[str] = None,
    down_column: Optional[str] = None,
    fps: Optional[float] = None,
    particle: Optional[float] = None,
    every_particle: bool = False,
) -> TrackTable:
    """A tracked run's table read as `rollphase track` reads it: format "plain" (the authors'
    CSV: frame, xn, yn), "tracker" (Tracker's data export: a title line, then t, x, y; tabs,
    commas, semicolons or spaces, decimal commas; frames are counted from the first time at
    fps, the rate read from the time steps unless given; x runs down the ramp) or "trackpy" (frame, particle, x, y;
    particle picks the body), told from the file when not given. frames, across and down are in
    the file's units (multiply by cm per unit); InputError names what cannot be read."""

def measure_track(
    frames: _Floats, down: _Floats, across: _Floats, *, markers: Optional[_Floats] = None
) -> TrackMeasurement:
    """`rollphase track`'s measurement of a centre track (frame numbers; down and across the
    ramp in cm, NaN where missing): cleaned, and its period found by FFT at every shift, stated
    only with its evidence (each cycle repeats on its own, surrogates set the chance level, most
    of the track repeats), else InputError saying why. Periods and shifts are in frames. With
    markers ((N, 3): frame, down, across in cm), marker_reading says whether their pattern
    repeats after one period or only after two, as `track --markers`. repeat_shown says how
    closely the period is shown: "roughly" where the centre varies from turn to turn beyond its
    noise (as a chaotic motion does) and no markers repeat."""

def compare_with_model(
    body: Body,
    alpha: float,
    *,
    period_s: float,
    advance_down_cm: float,
    advance_across_cm: float,
    mass_ratio: Optional[float] = None,
    scale_mm: Optional[float] = None,
    starts: int = 32,
    seed: int = 1,
    period_error_s: Optional[float] = None,
    folded: Optional[_Floats] = None,
    fps: Optional[float] = None,
) -> ModelComparison:
    """A measured motion beside the model's prediction, as `rollphase track --body` gives it:
    m/m0 and t0 solved together so that the model's period in seconds is the measured one
    (m/m0 = ⟨r⟩/(g t0²)), or at a given mass_ratio; with period_error_s (the period's standard
    error, from measure_track), mass_ratio_error and t0_error_s from it alone (None without
    it, or where m/m0 was given); the SI's speed estimate v²/(g⟨r⟩ sin²α)
    beside them; the nearest predicted orbit's period, advance and speed against the measured
    ones, and its path in cm; with folded (measure_track's) and fps (1e-5 to 1e6), also where
    the orbit sits on the folded track, as `track --body` draws it: phase, mirrored_across (how
    it is drawn), handedness_shown (whether the track shows which way round it runs),
    down_explained and across_explained (the shares of the track's variance explained)."""

def period_counts(
    body: Body,
    alpha: float,
    *,
    mass_ratio: float,
    orientations: int = 100,
    seed: int = 1,
    t_min: float = 2000.0,
    t_cap: float = 20000.0,
    max_k: int = 4,
    tol: float = 1e-5,
) -> PeriodCounts:
    """Fig. 4e: the period multiplicities of runs from random orientations at one m/m0. Keys:
    cycle_counts (k = 1..4, then none), at_rest, undecided, left_model (runs whose body left
    the ramp, counted with none: no cycle is claimed for them), longest_run."""

def mass_bifurcation(
    body: Body,
    alpha: float,
    *,
    masses: Sequence[float],
    starts: int = 4,
    seed: int = 1,
    t_min: float = 1500.0,
    t_cap: Optional[float] = None,
) -> MassBifurcation:
    """The orbit diagram in m/m0 (beyond Fig. 4e): the period-1 orbits continued in m with their
    Floquet multipliers, the flips where a multiplier passes −1, and the period-2 windows the
    runs show. masses ascend from 0. Keys: masses, period_counts (n, 5), orbits (mass_ratio,
    period, multipliers (k, 5) complex, most_negative_real), flips (orbit, mass_ratio,
    loses_stability), windows (orbit, onset_mass, end_mass, flip_onset_mass, flip_end_mass),
    undecided_runs, longest_run."""

class DesignReport(TypedDict):
    """What design() and check_design() say of a body, as `rollphase design --json` prints it."""

    holds: bool
    why_not: list[str]
    scale_mm: float
    design: dict[str, Any]

def design(
    dim: int,
    *,
    alpha_star: Optional[float] = None,
    hysteresis: Optional[Tuple[float, float]] = None,
    doubling: Optional[float] = None,
    drift: Optional[float] = None,
    orbits: Optional[int] = None,
    share: Optional[float] = None,
    mass_ratio: Optional[float] = None,
    alpha: Optional[float] = None,
    modes: int = 4,
    scale_mm: Optional[float] = None,
    min_radius_mm: float = 0.4,
    max_amplitude: float = 1.0,
    start: Optional[Body] = None,
    seed: int = 1,
    generations: int = 400,
    alpha_band: float = 0.005,
    mass_band: float = 0.2,
    surface_mm: float = 0.05,
    draws: int = 16,
    budget: Optional[float] = None,
) -> Tuple[Body, DesignReport]:
    """A printable body for the targets (alpha_star; hysteresis=(M, F) in 2D; doubling=M,
    drift=D or orbits=K (each of K from ≥ share of the starts, default 1/(2K)) with alpha= in
    3D, drift and orbits at mass_ratio, default viscous), found by CMA-ES (seeded) under the
    printer's constraints and checked at the precise setting over α ± alpha_band,
    m/m0 ± mass_band × m/m0 and draws print errors of ± surface_mm. Returns (body, report);
    report["holds"] says whether it holds over the band (a design that does not is returned,
    not raised), report["design"] the achieved values, margins, constraints, the check, and in
    "predicted" what the body does on each target's ramp in mm and s. budget (seconds, as
    --budget) ends the search early with the best body so far, checked as any other
    (report["design"]["ended"] == "stopped")."""

def check_design(
    body: Body,
    *,
    alpha_star: Optional[float] = None,
    hysteresis: Optional[Tuple[float, float]] = None,
    doubling: Optional[float] = None,
    drift: Optional[float] = None,
    orbits: Optional[int] = None,
    share: Optional[float] = None,
    mass_ratio: Optional[float] = None,
    alpha: Optional[float] = None,
    scale_mm: Optional[float] = None,
    min_radius_mm: float = 0.4,
    max_amplitude: float = 1.0,
    alpha_band: float = 0.005,
    mass_band: float = 0.2,
    surface_mm: float = 0.05,
    draws: int = 16,
    seed: int = 1,
) -> Tuple[Body, DesignReport]:
    """What design() would say of a body you have, without a search (`design --check-only`),
    at the body's own degree (any: a fitted print's too)."""
