"""Parameter sweep: peak contact force at the clearance joint against crank speed.

Each point loads the model with one override and runs it. ``Model.run`` releases the GIL,
so a plain ``ThreadPoolExecutor`` runs the points in parallel on all cores, with no
pickling and no worker processes:

    python python/examples/parameter_sweep.py

The same per-point function works with other executors (none of them is needed here):

* ``concurrent.futures.ProcessPoolExecutor``: the function is a top-level def, so it pickles;
* Dask: ``dask.compute(*[dask.delayed(peak_force)(rpm) for rpm in speeds])`` (the threaded
  scheduler is the right one, since the GIL is released);
* Ray: ``ray.get([ray.remote(peak_force).remote(rpm) for rpm in speeds])``.

Return plain numbers (or small arrays) from the point function rather than whole results,
so that the distributed frameworks move little data.
"""

import concurrent.futures
import os
import time

MODEL = "models/farahan2016.toml"


def peak_force(rpm: float) -> "tuple[float, int, float]":
    """(rpm, impacts, peak normal force in N) over two crank turns at `rpm`."""
    import linkdyn  # imported here so that process and cluster workers import it themselves

    model = linkdyn.load(MODEL, set={"drivers.motor.speed_rpm": rpm})
    joint = model.run(revs=2, dt=1e-4).summary["clearance_joints"][0]
    return rpm, joint["impact_count"], joint["peak_normal_force"]


if __name__ == "__main__":
    speeds = [250, 500, 1000, 2000, 3500]
    t0 = time.perf_counter()
    with concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count()) as pool:
        rows = list(pool.map(peak_force, speeds))
    elapsed = time.perf_counter() - t0
    print(f"{'rpm':>6} {'impacts':>8} {'peak F_N (N)':>13}")
    for rpm, impacts, force in rows:
        print(f"{rpm:>6} {impacts:>8} {force:>13.1f}")
    print(f"{len(speeds)} runs in {elapsed:.2f} s on {os.cpu_count()} CPUs")
