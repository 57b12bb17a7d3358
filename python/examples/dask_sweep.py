"""A parameter sweep written by hand, on whatever executor is at hand.

Each point loads models/farahan2016.toml at 3500 rpm with one radial clearance c and records
the coupler angle once per crank turn after a transient (``Model.poincare``): the points of a
bifurcation diagram. The same top-level point function runs on

* ``concurrent.futures.ThreadPoolExecutor`` (always): the analyses release the GIL, so
  threads run points in parallel with no pickling and no worker processes;
* ``concurrent.futures.ProcessPoolExecutor`` (always): the function and its result pickle;
* Dask (``dask.delayed``, threaded scheduler) and Ray (``ray.remote``), each only if it is
  installed; neither is a dependency of linkdyn.

Every executor must give the same numbers, bit for bit, as the built-in sweep
``Model.bifurcation`` (rayon threads inside Rust), which the script checks at the end. On a
cluster, point Dask's ``Client`` or ``ray.init(address=...)`` at it; the model file must be
readable by every worker under the same path, or send the workers its text
(``linkdyn.load(MODEL).to_toml()``) and load it there with ``linkdyn.loads`` (as
python/tests/test_dask_sweep.py does on a Dask ``LocalCluster``).

    python python/examples/dask_sweep.py

Run from the repository root. A few seconds of CPU.
"""

import concurrent.futures
import os
import time

import numpy as np

MODEL = "models/farahan2016.toml"
SPEED = {"drivers.motor.speed_rpm": 3500}
CLEARANCES = [2.0e-4, 2.5e-4, 3.0e-4, 3.5e-4, 4.0e-4, 4.5e-4]  # m
SECTION = dict(revs=20, transient=10, observe="coupler.phi", formulation="reduced")


def point(clearance: float) -> "tuple[float, np.ndarray, str]":
    """(c, coupler angle at turns 10 … 19 in rad, period verdict) at clearance c (m)."""
    import linkdyn  # imported here so that process and cluster workers import it themselves

    model = linkdyn.load(MODEL, set={**SPEED, "joints.B.clearance": clearance})
    s = model.poincare(**SECTION)
    # Return small plain data, not the whole record: distributed frameworks move little then.
    return clearance, s["coupler.phi"].copy(), s.verdict


def on(executor_class, workers):
    """Maps `point` over the clearances on a fresh executor, shut down afterwards."""

    def run():
        with executor_class(workers) as pool:
            return list(pool.map(point, CLEARANCES))

    return run


def timed(name, run):
    t0 = time.perf_counter()
    rows = run()
    print(f"{name:<28} {len(rows)} points in {time.perf_counter() - t0:5.2f} s")
    return name, rows


def with_dask():
    try:
        import dask
    except ImportError:
        return None
    # Threads suffice (the GIL is released); use a distributed Client for a cluster.
    return lambda: list(dask.compute(*[dask.delayed(point)(c) for c in CLEARANCES],
                                     scheduler="threads"))


def with_ray():
    try:
        import ray
    except ImportError:
        return None

    def run():
        ray.init(ignore_reinit_error=True, include_dashboard=False, log_to_driver=False)
        try:
            remote = ray.remote(point)
            return ray.get([remote.remote(c) for c in CLEARANCES])
        finally:
            ray.shutdown()

    return run


if __name__ == "__main__":
    import linkdyn

    workers = os.cpu_count() or 1
    results = [
        timed("ThreadPoolExecutor", on(concurrent.futures.ThreadPoolExecutor, workers)),
        timed("ProcessPoolExecutor", on(concurrent.futures.ProcessPoolExecutor, workers)),
    ]
    for name, make in [("dask (threads)", with_dask), ("ray", with_ray)]:
        run = make()
        if run is None:
            print(f"{name:<28} not installed, skipped")
        else:
            results.append(timed(name, run))

    # The built-in sweep over the same values: the reference.
    t0 = time.perf_counter()
    b = linkdyn.load(MODEL, set=SPEED).bifurcation(
        "joints.B.clearance", "coupler.phi", values=CLEARANCES, progress=False, **{
            k: v for k, v in SECTION.items() if k != "observe"})
    print(f"{'Model.bifurcation (rayon)':<28} {len(b.point_index)} points in "
          f"{time.perf_counter() - t0:5.2f} s")
    reference = b.value.reshape(len(CLEARANCES), -1)
    for name, rows in results:
        same = all(np.array_equal(values, reference[k]) for k, (_, values, _) in enumerate(rows))
        assert same, f"{name}: differs from Model.bifurcation"
    print("every executor gives Model.bifurcation's numbers, bit for bit")

    print(f"\n{'c (mm)':>7} {'verdict':>10} {'coupler.phi, last turn (rad)':>30}")
    for c, values, verdict in results[0][1]:
        print(f"{c * 1e3:>7.3f} {verdict:>10} {values[-1]:>30.9f}")
