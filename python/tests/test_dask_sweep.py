"""A bifurcation sweep through Dask's distributed scheduler gives ``linkdyn bifurcation``'s
diagram, point for point and bit for bit.

Two worker processes of a ``LocalCluster`` (as on a cluster: separate interpreters that receive
the task and its arguments pickled over a socket) each compute Poincaré sections of the
reference four-bar at 3500 rpm for some of the clearances; the model travels as its text
(``Model.to_toml``), so the workers need no shared file system. The command line computes the
same diagram with its rayon threads. Both run the library on the same model and settings, and
every recorded value is an f64 that crosses as its shortest round-trip text (CSV) or as a
pickled float64, so any difference is a lost setting or override, not rounding.

A few clearances and turns keep it to seconds; the cluster's start takes most of it.
"""

import pathlib

import numpy as np
import pytest

import linkdyn

from cli_files import first_difference, read, same_bits

distributed = pytest.importorskip("dask.distributed", reason="dask's distributed scheduler")

MODEL = "models/farahan2016.toml"
SPEED = "drivers.motor.speed_rpm=3500"
SECTION = dict(revs=8, transient=4, observe="coupler.phi", formulation="reduced")


def point(text: str, clearance: float):
    """One point of the diagram on a worker: (recorded turns, coupler angle at each, verdict)."""
    import linkdyn  # the worker's own import

    model = linkdyn.loads(text, set={"joints.B.clearance": clearance})
    s = model.poincare(**SECTION)
    return s.turn.copy(), s["coupler.phi"].copy(), s.verdict


def test_dask_distributed_sweep_is_linkdyn_bifurcation_point_for_point(cli, tmp_path):
    out = tmp_path / "bif.csv"
    code, _, err = cli(
        "bifurcation", MODEL, "--set", SPEED, "--param", "joints.B.clearance",
        "--from", "2e-4", "--to", "5e-4", "--steps", "3", "--revs", str(SECTION["revs"]),
        "--transient", str(SECTION["transient"]), "--observe", SECTION["observe"],
        "--formulation", SECTION["formulation"], "--out", str(out),
    )
    assert code == 0, err
    _, names, rows = read(out)
    assert names == ["index", "joints.B.clearance", "turn", "coupler.phi"], names
    _, _, verdict_rows = read(out.with_name("bif.verdicts.csv"))
    index = rows["index"].astype(int)
    clearances = [float(rows["joints.B.clearance"][index == k][0]) for k in np.unique(index)]
    assert len(clearances) == 4

    # The model with the speed override, as text: what each worker loads.
    text = linkdyn.load(MODEL, set=[SPEED]).to_toml()
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
        dashboard_address=None, scheduler_kwargs={"dashboard": False}, silence_logs=40,
    ) as cluster, distributed.Client(cluster) as client:
        futures = client.map(point, [text] * len(clearances), clearances)
        results = client.gather(futures)
        # Both workers took part (four tasks, two single-threaded processes): the sweep was
        # spread over processes, not run in this one.
        assert len(client.scheduler_info()["workers"]) == 2

    for k, (c, (turns, values, verdict)) in enumerate(zip(clearances, results)):
        mine = index == k
        assert same_bits(rows["turn"][mine], turns), f"point {k} (c = {c}): turns differ"
        assert same_bits(rows["coupler.phi"][mine], values), (
            f"point {k} (c = {c}): {first_difference(rows['coupler.phi'][mine], values)}"
        )
        # The command's verdict file says "period" with k in its own column; Python "period-k".
        cli_verdict = verdict_rows["verdict"][k]
        if cli_verdict == "period":
            cli_verdict = f"period-{int(float(verdict_rows['k'][k]))}"
        assert cli_verdict == verdict, (k, cli_verdict, verdict)
