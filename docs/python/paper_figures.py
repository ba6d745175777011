"""The paper's Fig. 3d and Fig. 4e from Python, with rollphase and matplotlib.

    python docs/python/paper_figures.py [OUT]      # writes OUT/fig3d.png and OUT/fig4e.png

Fig. 3d: the Poincaré map of viscous rolling on ∂Ω (the boundary of the SO(3) ball) for the
paper's body at α = 0.15, and its two stable periodic orbits with their Floquet multipliers.
Fig. 4e: where the body touches the ramp (the contact point, in the body) late in runs from
rest at m/m0 = 0, 6 and 10: one loop, a doubled loop at 6, one loop again at 10.
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt
import numpy as np

import rollphase

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
out.mkdir(parents=True, exist_ok=True)
body = rollphase.Body.paper_sphere(219)  # the paper's body: numpy seed 219, σ = 0.25, l ≤ 5
alpha = 0.15
clock = time.perf_counter()

# --- Fig. 3d: P(p) − p on the upper half of ∂Ω (p and −p are one orientation) --------------
n = 1200
z = 1 - (np.arange(n) + 0.5) / n  # a Fibonacci lattice on the upper hemisphere
phi = np.arange(n) * np.pi * (3 - np.sqrt(5)) % (2 * np.pi)
p = np.column_stack([np.sqrt(1 - z**2) * np.cos(phi), np.sqrt(1 - z**2) * np.sin(phi), z])
ends, times = rollphase.poincare_map(body, alpha, starts=np.column_stack([np.zeros(n), p]))
orbits = rollphase.periodic_orbits(body, alpha, orientations=32)


def disk_coords(v):
    """The upper hemisphere seen from +z (points of the lower one by their antipodes)."""
    v = np.where(v[..., 2:3] < 0, -v, v)
    return v[..., 0], v[..., 1]


x0, y0 = disk_coords(p)
x1, y1 = disk_coords(ends[:, 1:])
dx, dy = x1 - x0, y1 - y0
step = np.hypot(dx, dy)  # how far P moves p; short arrows show only the direction
fig, ax = plt.subplots(figsize=(6.4, 6.4))
ax.add_patch(plt.Circle((0, 0), 1, fill=False, color="0.6"))
arrows = ax.quiver(x0, y0, dx / step, dy / step, step, cmap="viridis", scale=40, width=0.003)
fig.colorbar(arrows, ax=ax, shrink=0.7, label="|P(p) − p| (seen from +z)")
for i, o in enumerate(orbits):
    x, y = disk_coords(o["point"])
    mu = ", ".join(f"{abs(m):.3f}" for m in o["multipliers"])
    ax.plot(x, y, "o", ms=11, mfc="none", mew=2, color=f"C{i + 1}",
            label=f"orbit {i + 1}: T = {o['period']:.2f}, |μ| = {mu}, {o['starts']} of 32 starts")
ax.set(aspect="equal", xlim=(-1.05, 1.05), ylim=(-1.05, 1.05), xlabel="p_x", ylabel="p_y",
       title=f"Poincaré map on ∂Ω, paper body, α = {alpha}")
ax.legend(loc="lower center", bbox_to_anchor=(0.5, -0.25), fontsize=8)
fig.savefig(out / "fig3d.png", dpi=120, bbox_inches="tight")

# --- Fig. 4e: the late contact path at m/m0 = 0, 6, 10 ------------------------------------
fig, axes = plt.subplots(1, 3, figsize=(12, 4.2), sharey=True)
for ax, mass in zip(axes, [0.0, 6.0, 10.0]):
    run = rollphase.simulate(body, alpha, 2400.0, mass_ratio=mass, contact=[2.0, 1.0],
                             samples=24001, rtol=1e-9)
    late = run.t >= 2000.0
    u = run.contact[late]
    counts = rollphase.period_counts(body, alpha, mass_ratio=mass, orientations=8)["cycle_counts"]
    k = 1 + int(np.argmax(counts[:4]))
    phi = np.arctan2(u[:, 1], u[:, 0])
    phi[1:][np.abs(np.diff(phi)) > np.pi] = np.nan  # no line across the seam at φ = ±π
    ax.plot(phi, u[:, 2], lw=0.8)
    ax.set(title=f"m/m0 = {mass:g}: period {k} ({counts[k - 1]} of 8 starts)",
           xlabel="contact azimuth φ", xlim=(-np.pi, np.pi))
axes[0].set_ylabel("contact cos θ")
fig.suptitle(f"Contact point in the body, t = 2000 … 2400, paper body, α = {alpha}")
fig.savefig(out / "fig4e.png", dpi=120, bbox_inches="tight")
print(f"wrote {out / 'fig3d.png'} and {out / 'fig4e.png'} in {time.perf_counter() - clock:.1f} s")
