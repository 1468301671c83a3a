"""The harness in Python: scenes, simulate of a scene by every method, suites, validate, the ocp
solvers. Each function runs the CLI's own code path, so the tests check that the Python results
are the CLI's (identical numbers) and that the summaries agree with the arrays returned.

Run through ctest (python_tests): PYTHONPATH, LGVI_TESTBED_EXE and LGVI_SOURCE_DIR are set there.
"""
import json
import os
import re
import runpy
import subprocess

import numpy as np
import pytest

import lgvi

pytestmark = pytest.mark.skipif(not lgvi.has_harness, reason="the module was built without the harness")

EXE = os.environ.get("LGVI_TESTBED_EXE", "")
SRC = os.environ.get("LGVI_SOURCE_DIR", "")


def cli_csv(path):
    """A CSV of the CLI as {column: array} (the '#' metadata lines skipped)."""
    with open(path) as f:
        lines = [line for line in f.read().splitlines() if not line.startswith("#")]
    header = lines[0].split(",")
    data = np.array([[float(x) for x in line.split(",")] for line in lines[1:]])
    return {name: data[:, i] for i, name in enumerate(header)}


def test_load_scene_and_simulate_returns_arrays_and_a_summary_that_agrees():
    scene = lgvi.load_scene("pendulum", t_final=0.5, output_every=5)
    assert (scene.system, scene.name, scene.steps) == ("pendulum", "pendulum", round(0.5 / scene.h))
    run = lgvi.simulate(scene)
    n = scene.steps // 5 + 1
    assert run["t"].shape == (n,) and run["R"].shape == (n, 3, 3) and run["Omega"].shape == (n, 3)
    assert np.array_equal(run["t"], run["columns"]["t"])
    s = run["summary"]
    assert s["status"] == "completed" and s["method"] == "lgvi" and s["output_rows"] == n
    assert lgvi.__version__ == s["version"] and re.fullmatch(r"\d+\.\d+\.\d+", lgvi.__version__)
    # The summary's diagnostics are maxima over the returned rows: computed from the same doubles
    # (the CSV holds them in round-trip form), so they agree exactly.
    E = run["columns"]["energy"]
    assert s["max_energy_error_absolute"] == np.abs(E - E[0]).max()
    assert s["max_energy_error_relative"] == np.abs(E - E[0]).max() / abs(E[0])
    RtR = np.einsum("nki,nkj->nij", run["R"], run["R"])
    assert s["max_orthogonality_error"] == pytest.approx(np.linalg.norm(RtR - np.eye(3), axis=(1, 2)).max(), abs=0)
    assert run["metadata"]["units"].startswith("t [s]")
    assert run["csv"] is None  # not kept
    # The energy trend is the least-squares line through the rows' E - E0, relative to |E0|.
    t = run["t"]
    slope = np.polyfit(t, (E - E[0]) / abs(E[0]), 1)[0]
    assert s["energy_drift_rate"] == pytest.approx(slope, rel=1e-8, abs=1e-14)
    assert s["energy_trend"] in ("drifts", "bounded")


def test_every_method_gives_the_cli_rows(tmp_path):
    """Every registered method on a short free-body scene: the arrays are the CLI's rows, number for
    number (the same code path: `lgvi-testbed simulate` and lgvi.simulate)."""
    scene = lgvi.load_scene("free-body", t_final=0.2)
    methods = lgvi.methods()
    assert {"lgvi", "composed-lgvi", "baseline"} <= {m["family"] for m in methods}
    assert {m["family"] for m in methods} <= {"lgvi", "composed-lgvi", "one-step", "baseline"}
    # The traits: the LGVIs are variational, stay on the group and keep the momentum map; a method
    # on coordinate models never claims to stay on the group.
    for m in methods:
        if m["family"] in ("lgvi", "composed-lgvi"):
            t = m["traits"]
            assert t["variational"] and t["stays_on_group"] and t["preserves_momentum_map"], m["name"]
        assert not (m["models"] and m["traits"]["stays_on_group"]), m["name"]
        assert m["traits"]["adaptive"] == (not m["fixed_step"]), m["name"]
    for m in methods:
        model = m["models"][0] if m["models"] else None
        rtol = None if m["fixed_step"] or m["family"] != "baseline" else 1e-8
        keep = tmp_path / (m["name"] + "-py.csv")
        run = lgvi.simulate(scene, method=m["name"], model=model, rtol=rtol, csv=keep)
        assert run["summary"]["status"] == "completed", (m["name"], run["summary"]["status_detail"])
        args = [EXE, "simulate", "free-body", "--t-final", "0.2", "--method", m["name"],
                "--out", str(tmp_path / (m["name"] + ".csv"))]
        if model:
            args += ["--model", model]
        if rtol:
            args += ["--rtol", str(rtol)]
        subprocess.run(args, check=True, capture_output=True)
        cli = cli_csv(tmp_path / (m["name"] + ".csv"))
        kept = cli_csv(keep)
        for column in ("t", "R11", "R23", "Omega1", "Omega3", "energy"):
            assert np.array_equal(run["columns"][column], cli[column]), (m["name"], column)
            assert np.array_equal(kept[column], cli[column]), (m["name"], column)
        assert np.array_equal(run["R"][:, 1, 2], cli["R23"])


def test_make_scene_is_the_scene_file_and_names_bad_fields():
    args = dict(parameters={"inertia": np.array([0.13, 0.28, 0.17])},
                initial={"R": np.eye(3), "Omega": [0.05, 0.05, 3.0]}, h=0.005, t_final=0.5, output_every=10)
    made = lgvi.make_scene("free-body", name="mine", **args)
    assert (made.name, made.system, made.steps, made.output_every) == ("mine", "free-body", 100, 10)
    with open(os.path.join(SRC, "experiments", "scenes", "free-body.toml")) as f:
        shipped = lgvi.parse_scene(f.read(), name="free-body", t_final=0.5)
    a, b = lgvi.simulate(made), lgvi.simulate(shipped)
    assert np.array_equal(a["R"], b["R"]) and np.array_equal(a["Omega"], b["Omega"])
    # Validated like a file: J = (1, 1, 3) violates the triangle inequality 1 + 1 >= 3.
    spin = {"Omega": [0.0, 0.0, 1.0]}
    with pytest.raises(ValueError, match=r"mine\.toml: parameters\.inertia: .*triangle"):
        lgvi.make_scene("free-body", {"inertia": [1.0, 1.0, 3.0]}, spin, h=0.1, t_final=1.0, name="mine")
    with pytest.raises(ValueError, match=r"parameters\.mass: unknown key"):
        lgvi.make_scene("free-body", {"inertia": [1.0, 2.0, 2.5], "mass": 1.0}, spin, h=0.1, t_final=1.0)
    with pytest.raises(ValueError, match=r"parameters\.inertia: not a number"):
        lgvi.make_scene("free-body", {"inertia": object()}, spin, h=0.1, t_final=1.0)
    with pytest.raises(ValueError, match=r"integration\.h"):
        lgvi.make_scene("free-body", {"inertia": [1.0, 2.0, 2.5]}, spin, h=-0.1, t_final=1.0)
    with pytest.raises(ValueError, match="method"):
        lgvi.simulate(made, method="no-such-method")
    with pytest.raises(ValueError, match="csv"):
        lgvi.simulate(made, csv="-")
    # A baseline without a model runs the quaternion model (as a study file's entry does).
    assert lgvi.simulate(made, method="cvode-bdf")["summary"]["model"] == "quaternion"
    assert "free-body" in lgvi.scene_names()


def test_run_suite_returns_the_summary_rows(tmp_path):
    """The default suite over a scenes directory of one short scene: two cases (the symmetric and
    the printed LGVI), rows as dicts that agree with lgvi.simulate of the same scene and form."""
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    with open(os.path.join(SRC, "experiments", "scenes", "pendulum.toml")) as f:
        text = f.read().replace("t_final = 20.0", "t_final = 0.2")
    (scenes / "tiny.toml").write_text(text)
    cases = lgvi.suite_cases("default", scenes_dir=scenes)
    assert [c["id"] for c in cases] == ["tiny-symmetric", "tiny-printed"]
    rows = lgvi.run_suite("default", tmp_path / "out", scenes_dir=scenes)
    assert [r["case"] for r in rows] == ["tiny-symmetric", "tiny-printed"]
    assert all(r["status"] == "completed" and r["as_expected"] for r in rows)
    for r in rows:
        run = lgvi.simulate(lgvi.load_scene(str(scenes / "tiny.toml"), form=r["form"]))
        assert r["max_energy_error_relative"] == run["summary"]["max_energy_error_relative"]
        assert r["solver_steps"] == run["summary"]["solver_steps"]
    # summary.csv states its units and the meaning of its error columns before the header.
    head = (tmp_path / "out" / "summary.csv").read_text().splitlines()
    assert "# suite: default" in head and any(line.startswith("# units: ") for line in head)
    assert any(line.startswith("# columns.max_energy_error_relative: ") for line in head)
    assert ("default", "every scene of the scenes directory with the symmetric and the printed LGVI") in lgvi.suites()


def test_validate_returns_the_table_and_catches_a_changed_value(tmp_path):
    """validate's exact group (free-body and Lagrange-top errors against their exact solutions):
    against the shipped accepted values every metric passes; against an accepted file with one
    truncation error halved, that metric (now twice the accepted, gated at 1e-6 relative) is
    REGRESSED and the others still pass."""
    report = lgvi.validate(quick=True, only=["exact"])
    assert report["form"] == "quick" and report["rows"]
    assert {r["verdict"] for r in report["rows"]} == {"pass"}, report["table"]
    assert report["counts"]["pass"] == len(report["rows"]) and not report["regressed"]
    assert all(r["name"].startswith("exact/") and np.isfinite(r["now"]) for r in report["rows"])
    changed = next(r for r in report["rows"] if r["kind"] == "truncation")
    lines = ["# form: quick"] + [f"{r['name']} {r['kind']} {r['now'] * (0.5 if r is changed else 1)!r}"
                                 for r in report["rows"]]
    edited = tmp_path / "accepted.txt"
    edited.write_text("\n".join(lines) + "\n")
    again = lgvi.validate(quick=True, only=["exact"], accepted=edited)
    verdicts = {r["name"]: r["verdict"] for r in again["rows"]}
    assert verdicts.pop(changed["name"]) == "REGRESSED" and again["regressed"]
    assert set(verdicts.values()) == {"pass"}
    with pytest.raises(ValueError, match="--only"):
        lgvi.validate(only=["nonsense"])


def test_ocp_indirect_and_direct_with_both_solvers():
    pend = lgvi.solve_ocp("pendulum", form="symmetric", steps=100)
    s = pend["summary"]
    assert pend["converged"] and s["converged"] and s["violation"] < 1e-10
    t = pend["trajectory"]
    assert t["t"].shape == (101,) and t["R"].shape == (101, 3, 3)
    # The terminal attitude is the target, 180 deg about the vertical, to the violation.
    assert np.abs(t["R"][-1] - np.diag([-1.0, -1.0, 1.0])).max() < 1e-9
    # The same discrete problem as solve_pendulum_transfer (symmetric form, h = 0.01): same cost.
    assert s["cost"] == pytest.approx(lgvi.solve_pendulum_transfer(h=0.01)["summary"]["cost"], rel=1e-9)

    # The direct method (paper's transcription: 7 not-a-knot knots per control, h = 0.01), single
    # shooting by SLSQP and multiple shooting by IPOPT. The landscape has several local optima
    # (lgvi/ocp/README.md): IPOPT from the default guess and SLSQP from the first seeded random
    # start reach the same one, 281.23; a cost of a fixed transcription is pinned by the
    # solvers' tolerances (violation 1e-10, stationarity) to ~1e-12 relative, gated at 1e-9 as
    # validate's cost kind is.
    ipopt = lgvi.solve_ocp("cart-pendulum", solver="ipopt")
    slsqp = lgvi.solve_ocp("cart-pendulum", solver="slsqp", first_start=1, starts=1)
    for res in (ipopt, slsqp):
        assert res["converged"], res["summary"]["status_detail"]
        assert res["summary"]["violation"] <= res["summary"]["tolerance"] == 1e-10
        assert res["trajectory"]["R"].shape == (res["summary"]["steps"] + 1, 3, 3)
    assert ipopt["summary"]["solver"] != slsqp["summary"]["solver"]
    assert ipopt["summary"]["cost"] == pytest.approx(slsqp["summary"]["cost"], rel=1e-9)
    assert slsqp["knots"]["columns"]["u1"].shape == (7,)
    with pytest.raises(ValueError, match="--solver|solver"):
        lgvi.solve_ocp("cart-pendulum", solver="nope", steps=100)
    with pytest.raises(ValueError, match="bicycle: unknown scene"):
        lgvi.solve_ocp("bicycle")
    with pytest.raises(TypeError, match="unexpected keyword argument 'stepz'"):
        lgvi.solve_ocp("pendulum", stepz=10)


def test_the_readme_quick_start_scene_loads_and_runs():
    """The TOML block after <!-- quick-start-scene --> in README.md is a valid scene."""
    with open(os.path.join(SRC, "README.md")) as f:
        readme = f.read()
    block = readme.split("<!-- quick-start-scene -->", 1)[1].split("```toml\n", 1)[1].split("```", 1)[0]
    scene = lgvi.parse_scene(block, name="my-top", t_final=0.1)
    assert scene.system == "pendulum"
    assert lgvi.simulate(scene)["summary"]["status"] == "completed"


def test_quick_start_example_runs():
    """examples/python/quick_start.py, the notebook-style example, runs to its end."""
    runpy.run_path(os.path.join(SRC, "examples", "python", "quick_start.py"), run_name="__main__")


def test_the_hairer_lubich_wanner_body_runs_with_its_key():
    """The literature's (2, 1, 2/3) body: its scene asks for nonphysical_inertia; the library's
    FreeRigidBody takes the same as a keyword and refuses the moments without it."""
    run = lgvi.simulate(lgvi.load_scene("hlw-rigid-body"))
    assert run["summary"]["status"] == "completed"
    y = run["Omega"] * np.array([2.0, 1.0, 2.0 / 3.0])  # body momentum: |y| is conserved
    assert np.abs(np.linalg.norm(y, axis=1) - 1.0).max() < 1e-12
    with pytest.raises(ValueError, match="triangle inequality"):
        lgvi.FreeRigidBody(np.array([2.0, 1.0, 2.0 / 3.0]))
    body = lgvi.FreeRigidBody(np.array([2.0, 1.0, 2.0 / 3.0]), nonphysical_inertia=True)
    assert np.allclose(body.inertia, np.diag([2.0, 1.0, 2.0 / 3.0]))


# --- the CLI's limits (issue 34, N8) --------------------------------------------------------------

@pytest.mark.parametrize("call, match", [
    # a tolerance the CLI refuses (--rtol 2.0) used to run from Python
    (lambda: lgvi.simulate(lgvi.load_scene("free-body"), method="cvode-bdf", model="quaternion", rtol=2.0),
     r"rtol: must be a number in \[1e-14, 0.1\] \(got 2\)"),
    (lambda: lgvi.simulate(lgvi.load_scene("free-body"), method="odeint-rkf78", model="quaternion", atol=1e-300),
     r"atol: is below round-off"),
    (lambda: lgvi.simulate(lgvi.load_scene("free-body"), method="rkmk45", rtol=0.5), r"rtol: .*\[1e-14, 0.1\]"),
    # a run whose rows would not fit in memory (the CLI streams its CSV instead)
    (lambda: lgvi.simulate(lgvi.load_scene("pendulum", h=1e-4, t_final=1e5, output_every=1)),
     r"output_every: the scene's steps / output_every \(1000000000 / 1\) give 1000000002 rows"),
    # the [ocp] scenes' step cap, from either side (10^7 steps took 3.8 GB)
    (lambda: lgvi.load_scene("ocp-pendulum", h=1e-7), r"integration\.h \(--h\): gives 10000000 steps"),
    (lambda: lgvi.solve_ocp("pendulum", steps=10**8), r"steps: must be an integer in \[1, 1000000\]"),
    # the ocp options' ranges, named as Python's arguments
    (lambda: lgvi.solve_ocp("pendulum", max_iterations=0), r"max_iterations: must be an integer in \[1, 1000000\]"),
    (lambda: lgvi.solve_ocp("pendulum", lm_damping=-1.0), r"lm_damping: must be a number in \(0, 1e10\]"),
    (lambda: lgvi.solve_ocp("dumbbell", sphere_radius=0.0), r"sphere_radius: must be a number in \(0, 1e100\]"),
    (lambda: lgvi.solve_ocp("cart-pendulum", tolerance=2.0), r"tolerance: must be a number in \(0, 0.1\]"),
    (lambda: lgvi.solve_ocp("cart-pendulum", starts=0), r"starts: must be an integer in \[1, 10000\]"),
    (lambda: lgvi.solve_ocp("cart-pendulum", knots=10**12), r"knots: must be an integer in \[3, 1000\]"),
])
def test_the_clis_limits_raise_value_error_naming_the_argument(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_make_scene_writes_every_value_as_the_scene_file_reads_it():
    """make_scene writes its arguments as TOML text (its own writer: toml++'s formatter has
    undefined behaviour for floats below 1): floats round-trip to the same double, strings keep
    quotes, backslashes and control characters, and a non-finite number is named by the parser."""
    spin = {"Omega": [0.0, 0.0, 1.0]}
    inertia = [0.1 + 0.2, 2.0 / 3.0, 0.9]  # shortest round-trip digits: 0.30000000000000004
    made = lgvi.make_scene("free-body", {"inertia": np.array(inertia)}, spin, h=1e-3, t_final=3e-3,
                           name="odd", description='a "quoted"\\ name\twith\ncontrol characters\x01')
    assert made.steps == 3
    assert made.description == 'a "quoted"\\ name\twith\ncontrol characters\x01'
    run = lgvi.simulate(made)
    direct = lgvi.parse_scene('system = "free-body"\n[parameters]\ninertia = [0.30000000000000004, '
                              '0.6666666666666666, 0.9]\n[initial]\nOmega = [0.0, 0.0, 1.0]\n'
                              '[integration]\nh = 0.001\nt_final = 0.003\n', name="direct")
    assert np.array_equal(run["Omega"], lgvi.simulate(direct)["Omega"])
    for bad in (float("inf"), float("nan")):
        with pytest.raises(ValueError, match=r"parameters\.inertia"):
            lgvi.make_scene("free-body", {"inertia": [1.0, 2.0, bad]}, spin, h=0.1, t_final=1.0)
