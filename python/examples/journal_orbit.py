"""Journal orbit of the clearance joint B of the Farahan et al. (2016) four-bar.

Runs models/farahan2016.toml (crank at 250 rpm, radial clearance c = 0.5 mm) for two crank
turns and plots the eccentricity (B.ex, B.ey) of the journal centre relative to the bearing
centre, inside the clearance circle |e| = c, with the located impacts marked. The free
flights are the arcs across the circle; contact is on (or a few µm beyond) the circle.

    python python/examples/journal_orbit.py [OUT.png]

Needs matplotlib (``pip install matplotlib``). Run from the repository root.
"""

# %% Run
import sys

import numpy as np

import linkdyn

model = linkdyn.load("models/farahan2016.toml")
result = model.run(revs=2, dt=1e-5)
c = next(j["clearance"] for j in model.joints if j["name"] == "B")
ex, ey = result["B.ex"], result["B.ey"]
summary = result.summary["clearance_joints"][0]
print(
    f"{len(result)} samples, {summary['impact_count']} impacts, "
    f"max penetration {summary['max_penetration'] * 1e6:.1f} µm, "
    f"peak normal force {summary['peak_normal_force']:.0f} N"
)

# %% Plot (in mm)
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

fig, ax = plt.subplots(figsize=(6, 6))
theta = np.linspace(0, 2 * np.pi, 400)
ax.plot(c * 1e3 * np.cos(theta), c * 1e3 * np.sin(theta), "k--", lw=1, label=f"clearance circle (c = {c * 1e3:g} mm)")
ax.plot(ex * 1e3, ey * 1e3, lw=0.7, label="journal centre")
impacts = [e["t"] for e in result.events if e["kind"] == "impact"]
if impacts:
    # Positions at the impacts from the samples (dt = 10 µs), by linear interpolation.
    ax.plot(np.interp(impacts, result.t, ex) * 1e3, np.interp(impacts, result.t, ey) * 1e3,
            "r.", ms=5, label=f"impacts ({len(impacts)})")
ax.plot(ex[0] * 1e3, ey[0] * 1e3, "ko", ms=4, label="start (centred)")
ax.set_aspect("equal")
lim = 1.15 * c * 1e3
ax.set_xlim(-lim, lim)
ax.set_ylim(-lim, lim)
ax.set_xlabel("$e_x$ (mm)")
ax.set_ylabel("$e_y$ (mm)")
ax.set_title(f"{model.name}: journal orbit at B, 2 crank turns at 250 rpm")
ax.legend(loc="lower left", fontsize=8)
out = sys.argv[1] if len(sys.argv) > 1 else "journal_orbit.png"
fig.savefig(out, dpi=150, bbox_inches="tight")
print(f"wrote {out}")
