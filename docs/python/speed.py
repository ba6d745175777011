"""rollphase from Python beside a SciPy reference written as the paper's authors wrote theirs.

    python docs/python/speed.py [--starts 5000]

1. The 3D viscous run of the paper's body (numpy seed 219) at α = 0.15, t = 0 … 100, rtol 1e-10,
   from rest with the body point at θ = 2, φ = 1 on the ramp:
   rollphase.simulate (the call, median of 20) beside a pure SciPy version of the same model in
   this process (solve_ivp DOP853 at rtol 1e-10, the contact found at every right-hand side by
   maximising the support function r(u) u·d by Newton's method on (θ, φ), r(u) and its
   derivatives from scipy.special's spherical harmonics), and beside the 13.2 s the authors' notebook takes (issue 24). Both end
   states are printed, so the reference is seen to be the same physics.
2. simulate_many over N random starts (101 samples each) beside a Python loop of simulate.
Prints a Markdown table.
"""

import argparse
import json
import statistics
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.special import sph_harm_y

import rollphase

AUTHORS_SECONDS = 13.2
ALPHA, T_END, RTOL = 0.15, 100.0, 1e-10

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--starts", type=int, default=5000)
args = parser.parse_args()

body = rollphase.Body.paper_sphere(219)
coeffs = json.loads(body.to_json())["coeffs"]


# --- The SciPy reference ------------------------------------------------------------------
L = np.array([c["l"] for c in coeffs])
M = np.array([c["m"] for c in coeffs])
WEIGHT = np.array([c["re"] + 1j * c["im"] for c in coeffs]) / (L * (L + 1))


def radius_jet(theta, phi):
    """r and its first and second derivatives in (θ, φ), from scipy.special's harmonics."""
    y, dy, d2y = sph_harm_y(L, M, theta, phi, diff_n=2)
    r = 1.0 + (WEIGHT * y).sum().real
    return r, (WEIGHT[:, None] * dy).sum(0).real, (WEIGHT[:, None, None] * d2y).sum(0).real


def frame(theta, phi):
    """u(θ, φ) and its first and second derivatives."""
    st, ct, sp, cp = np.sin(theta), np.cos(theta), np.sin(phi), np.cos(phi)
    u = np.array([st * cp, st * sp, ct])
    du = np.array([[ct * cp, ct * sp, -st], [-st * sp, st * cp, 0.0]])
    d2u = np.array([[-u, [-ct * sp, ct * cp, 0.0]], [[-ct * sp, ct * cp, 0.0], [-st * cp, -st * sp, 0.0]]])
    return u, du, d2u


def rotate(q, v):
    """v turned by the unit quaternion q = (w, x, y, z)."""
    w, x, y, z = q
    u = np.array([x, y, z])
    return v + 2 * np.cross(u, np.cross(u, v) + w * v)


class Contact:
    """The support point in body direction d: the maximum of h = r(u) u·d over the sphere of
    directions, by Newton's method on (θ, φ) with exact derivatives, warm-started."""

    def __init__(self):
        self.angles = None

    def __call__(self, d):
        a = self.angles
        if a is None or np.dot(frame(*a)[0], d) < 0.5:
            a = np.array([np.arccos(np.clip(d[2], -1, 1)), np.arctan2(d[1], d[0])])
        for _ in range(30):
            r, g, hess = radius_jet(*a)
            u, du, d2u = frame(*a)
            ud, dud, d2ud = u @ d, du @ d, d2u @ d
            grad = g * ud + r * dud
            h2 = hess * ud + np.outer(g, dud) + np.outer(dud, g) + r * d2ud
            step = np.linalg.solve(h2, -grad)
            a = a + step
            if np.abs(step).max() < 1e-14:
                break
        self.angles = a
        return radius_jet(*a)[0] * frame(*a)[0]


force = np.array([np.sin(ALPHA), 0.0, -np.cos(ALPHA)])
contact = Contact()


def rhs(t, y):
    q = y[:4] / np.linalg.norm(y[:4])
    conj = q * np.array([1, -1, -1, -1])
    d = rotate(conj, np.array([0.0, 0.0, -1.0]))  # the ramp's normal in the body
    r = rotate(q, contact(d))  # contact → lab, from the centre
    omega = -np.cross(r, force)  # γ = 1
    w, x, yq, z = q
    qdot = 0.5 * np.array([
        -omega @ [x, yq, z],
        omega[0] * w + omega[1] * z - omega[2] * yq,
        omega[1] * w + omega[2] * x - omega[0] * z,
        omega[2] * w + omega[0] * yq - omega[1] * x,
    ])
    v = -np.cross(omega, r)
    return np.concatenate([qdot, v[:2]])


# The same start for both: the body point at θ = 2, φ = 1 on the ramp (away from the poles of
# the reference's (θ, φ) chart, where its Newton step is singular).
START = dict(contact=(2.0, 1.0))
run = rollphase.simulate(body, ALPHA, T_END, rtol=RTOL, samples=2, **START)
q0 = run.q[0]

clock = time.perf_counter()
ref = solve_ivp(rhs, (0, T_END), np.concatenate([q0, [0.0, 0.0]]), method="DOP853",
                rtol=RTOL, atol=RTOL)
scipy_seconds = time.perf_counter() - clock
q_ref = ref.y[:4, -1] / np.linalg.norm(ref.y[:4, -1])

calls = []
for _ in range(20):
    clock = time.perf_counter()
    run = rollphase.simulate(body, ALPHA, T_END, rtol=RTOL, **START)
    calls.append(time.perf_counter() - clock)
ours = statistics.median(calls)
agree = min(np.abs(run.q[-1] - q_ref).max(), np.abs(run.q[-1] + q_ref).max())
dx = abs((run.com[-1, 0] - run.com[0, 0]) - ref.y[4, -1])

# --- simulate_many against a loop ----------------------------------------------------------
rng = np.random.default_rng(1)
q0s = rng.normal(size=(args.starts, 4))
clock = time.perf_counter()
many = rollphase.simulate_many(body, ALPHA, T_END, q0s=q0s, rtol=RTOL, samples=101)
many_seconds = time.perf_counter() - clock
clock = time.perf_counter()
for q in q0s:
    rollphase.simulate(body, ALPHA, T_END, q0=q, rtol=RTOL, samples=101)
loop_seconds = time.perf_counter() - clock

print("| what | wall time | speed-up |")
print("|---|---|---|")
print(f"| authors' notebook (solve_ivp), issue 24 | {AUTHORS_SECONDS} s | 1× |")
print(f"| SciPy reference (this script, {ref.nfev} right-hand sides) | {scipy_seconds:.2f} s | "
      f"{AUTHORS_SECONDS / scipy_seconds:.1f}× |")
print(f"| `rollphase.simulate`, median of 20 calls | {ours * 1e3:.2f} ms | "
      f"{AUTHORS_SECONDS / ours:,.0f}× the authors', {scipy_seconds / ours:,.0f}× the SciPy reference |")
print(f"| `simulate_many`, {args.starts} starts, 101 samples | {many_seconds:.2f} s | "
      f"{loop_seconds / many_seconds:.2f}× the loop below |")
print(f"| Python loop of `simulate`, same starts | {loop_seconds:.2f} s | |")
print()
print(f"End states agree: max |q_rollphase − q_scipy| = {agree:.1e}, |Δx| = {dx:.1e} "
      f"(x = {ref.y[4, -1]:.6f} downhill at t = {T_END:g})")
