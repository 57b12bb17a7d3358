"""Poincaré sections of the journal centre at the clearance joint B (Farahan et al. 2016,
Figs. 5b–c and 6c–d).

The four-bar of models/farahan2016.toml (reduced Lagrangian formulation, as in the paper) at
its two speeds: 250 rpm with c = 0.5 mm, and 3500 rpm with c = 0.44 mm. The journal's
eccentricity (B.ex, B.ey) is recorded once per crank turn, at the exact instants t_k = k·T, for
turns 1 … REVS − 1 (turn 0 is the centred start). The two sections run in two threads at once
(``Model.poincare`` releases the GIL). Panels (a) and (b) show the points coloured by turn;
panel (c) the distance of each point from the last one against the turn, with the period
tolerance of the verdict: the points settle onto one fixed point, period one.

The paper reports chaotic rattling at 250 rpm; with its parameters as shipped (friction
included) linkdyn finds period one there as well, settled within a few turns (see
docs/sweeps.md, "Measured behaviour used by the tests").

    python python/examples/poincare_figure.py [OUT.png [REVS]]

Needs matplotlib (``pip install matplotlib``); draws off-screen (Agg) when there is no display.
Run from the repository root. About 2 s of CPU for the default 60 turns.
"""

# %% Compute both sections, in parallel threads
import concurrent.futures
import os
import sys

import numpy as np

import linkdyn

MODEL = "models/farahan2016.toml"
out = sys.argv[1] if len(sys.argv) > 1 else "poincare_figure.png"
revs = int(sys.argv[2]) if len(sys.argv) > 2 else 60
cases = {
    "250 rpm, c = 0.5 mm": {"drivers.motor.speed_rpm": 250},
    "3500 rpm, c = 0.44 mm": {"drivers.motor.speed_rpm": 3500, "joints.B.clearance": 0.00044},
}


def section(overrides):
    model = linkdyn.load(MODEL, set=overrides)
    return model.poincare(revs=revs, transient=1, observe=["B.ex", "B.ey"],
                          formulation="reduced")


with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
    sections = dict(zip(cases, pool.map(section, cases.values())))
for name, s in sections.items():
    print(f"{name}: {len(s)} points, {s.verdict}"
          + (f", settled from turn {s.settled_at_turn}" if s.settled_at_turn is not None else ""))

# %% Plot (µm)
import matplotlib

if not os.environ.get("DISPLAY") and not os.environ.get("MPLBACKEND"):
    matplotlib.use("Agg")
import matplotlib.pyplot as plt

fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
for ax, (name, s), letter in zip(axes, sections.items(), "ab"):
    ex, ey = s["B.ex"] * 1e6, s["B.ey"] * 1e6
    points = ax.scatter(ex, ey, c=s.turn, cmap="viridis", s=14)
    ax.plot(ex[-1], ey[-1], "r+", ms=14, label=f"turn {s.turn[-1]}")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("$e_x$ (µm)")
    ax.set_ylabel("$e_y$ (µm)")
    ax.set_title(f"({letter}) {name}: {s.verdict}")
    ax.legend(loc="best", fontsize=8)
    fig.colorbar(points, ax=ax, label="crank turn")

ax = axes[2]
for name, s in sections.items():
    distance = np.hypot(*(s.points - s.points[-1]).T) * 1e6
    line, = ax.semilogy(s.turn[:-1], distance[:-1], ".-", label=name)
    ax.axhline(np.hypot(*s.tolerance) * 1e6, color=line.get_color(), ls=":", lw=1.5)
ax.set_xlabel("crank turn k")
ax.set_ylabel("$|e_k - e_{last}|$ (µm)")
ax.set_title("(c) distance from the last point")
ax.text(0.98, 0.97, "dotted: period tolerance of the verdict", transform=ax.transAxes,
        ha="right", va="top", fontsize=8)
ax.legend(fontsize=8)
fig.suptitle(f"{MODEL}: Poincaré sections of the journal centre at B, once per crank turn")
fig.savefig(out, dpi=130)
print(f"wrote {out}")
