"""The package face of lgvi: signatures, docstrings and stubs for every function; solve_ocp and
run_study as the CLI's ocp and study; the CLI's bad options refused alike from Python.

Run through ctest (python_tests): PYTHONPATH, LGVI_TESTBED_EXE and LGVI_SOURCE_DIR are set there."""
import inspect
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import lgvi

HERE = os.path.dirname(os.path.abspath(__file__))
EXE = os.environ.get("LGVI_TESTBED_EXE", "")
harness = pytest.mark.skipif(not lgvi.has_harness, reason="the module was built without the harness")


def public_callables():
    """(qualified name, callable) of every public function and method of the package."""
    out = []
    for namespace, prefix in ((lgvi, "lgvi."), (lgvi.so3, "lgvi.so3.")):
        for name in sorted(dir(namespace)):
            value = getattr(namespace, name)
            if name.startswith("_") or name == "so3":
                continue
            if isinstance(value, type):
                for attr, member in vars(value).items():
                    if attr == "__init__" or not attr.startswith("_"):
                        if callable(member) or isinstance(member, staticmethod):
                            out.append((prefix + name + "." + attr, getattr(value, attr)))
                if hasattr(value.__init__, "__signature__"):  # Scene has no constructor (load_scene, ... make one)
                    out.append((prefix + name, value))
            elif callable(value):
                out.append((prefix + name, value))
    return out


@pytest.mark.parametrize("name, function", public_callables(), ids=lambda x: x if isinstance(x, str) else "")
def test_every_function_has_a_signature_and_a_docstring(name, function):
    signature = inspect.signature(function)  # raised ValueError for a compiled function before
    doc = inspect.getdoc(function) or ""
    if not name.endswith("__init__"):
        assert len(doc) > 20, f"{name}: no docstring"
    # The names are those the function takes: calling by them binds.
    for parameter in signature.parameters.values():
        assert re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", parameter.name), (name, parameter.name)


def test_signatures_bind_the_arguments_by_their_names():
    sig = inspect.signature(lgvi.load_scene)
    assert list(sig.parameters)[:3] == ["scene", "scenes_dir", "h"]
    assert sig.parameters["h"].default is None
    assert inspect.signature(lgvi.make_scene).parameters["h"].kind is inspect.Parameter.KEYWORD_ONLY
    R = lgvi.so3.exp(np.array([0.1, 0.2, 0.3]))
    assert np.allclose(lgvi.so3.log(R=R), [0.1, 0.2, 0.3], atol=1e-15)
    assert lgvi.__version__.count(".") == 2


@harness
def test_the_stubs_are_those_of_the_package():
    """python/lgvi/*.pyi are what make_stubs.py writes for this build: regenerate with
    `PYTHONPATH=build/python python3 python/make_stubs.py python/lgvi`."""
    sys.path.insert(0, os.path.dirname(HERE))
    try:
        import make_stubs
    finally:
        sys.path.pop(0)
    for file, text in make_stubs.stubs().items():
        with open(os.path.join(os.path.dirname(HERE), "lgvi", file)) as committed:
            assert committed.read() == text, f"python/lgvi/{file} is stale: run python/make_stubs.py"


def test_the_example_notebook_is_written_from_its_percent_file():
    """examples/python/quick_start.ipynb is what percent_to_notebook.py writes from quick_start.py
    (regenerate: python3 python/percent_to_notebook.py examples/python/quick_start.py
    examples/python/quick_start.ipynb)."""
    sys.path.insert(0, os.path.dirname(HERE))
    try:
        import percent_to_notebook
    finally:
        sys.path.pop(0)
    examples = os.path.join(os.path.dirname(os.path.dirname(HERE)), "examples", "python")
    with open(os.path.join(examples, "quick_start.py")) as source, \
            open(os.path.join(examples, "quick_start.ipynb")) as committed:
        assert committed.read() == percent_to_notebook.notebook(source.read()), "quick_start.ipynb is stale"


@harness
def test_solve_ocp_takes_a_scene_and_overrides_W_and_the_horizon(tmp_path):
    """A Scene made in memory is the same problem as its file; W, steps and t_final override it.
    Scaling the cost, W = c I, leaves the minimizer u* unchanged (u = -W^{-1} B^T lambda with the
    multipliers scaled by c), so J(c I) = c J(I) and lambda_0(c I) = c lambda_0(I); checked to the
    shooting's tolerance (|r| <= 1e-12 moves J by ~1e-12 relative; gated at 1e-9)."""
    base = lgvi.solve_ocp("free-body-slew")
    scene = lgvi.load_scene("ocp-free-body-slew")
    same = lgvi.solve_ocp(scene)
    assert same["summary"]["cost"] == pytest.approx(base["summary"]["cost"], rel=1e-12)
    doubled = lgvi.solve_ocp(scene, W=[2.0, 2.0, 2.0])
    assert doubled["converged"]
    assert np.array_equal(doubled["summary"]["W"], 2.0 * np.eye(3))
    assert doubled["summary"]["cost"] == pytest.approx(2.0 * base["summary"]["cost"], rel=1e-9)
    assert np.allclose(doubled["summary"]["multiplier"], 2.0 * np.array(base["summary"]["multiplier"]), rtol=1e-9)
    full = lgvi.solve_ocp(scene, W=np.diag([2.0, 2.0, 2.0]))
    assert full["summary"]["cost"] == pytest.approx(doubled["summary"]["cost"], rel=1e-12)
    text = open(scene.file).read()
    parsed = lgvi.parse_scene(text, name="my-slew")
    shorter = lgvi.solve_ocp(parsed, steps=50)
    assert shorter["summary"]["steps"] == 50 and shorter["converged"]
    with pytest.raises(ValueError, match=r"W: needs 3 values \(the diagonal\) or 9"):
        lgvi.solve_ocp(scene, W=[1.0, 2.0])
    with pytest.raises(ValueError, match=r"W: is not positive definite"):
        lgvi.solve_ocp(scene, W=[1.0, -1.0, 1.0])
    with pytest.raises(ValueError, match=r"W: expected the diagonal"):
        lgvi.solve_ocp(scene, W="identity")
    with pytest.raises(TypeError, match="unexpected keyword argument 'stepz'"):
        lgvi.solve_ocp(scene, stepz=3)


@harness
def test_run_study_is_the_cli_study(tmp_path):
    study = tmp_path / "tiny.toml"
    study.write_text('name = "tiny"\nmetrics = ["energy", "final-error"]\n'
                     'scenes = [{ scene = "free-body", horizons = [1.0] }]\n'
                     'methods = ["lgvi", { method = "odeint-rk4", model = "quaternion" }]\n'
                     'steps = [100, 200]\ntolerances = [1e-6]\nreference = { kind = "exact" }\n')
    rows = lgvi.run_study(str(study), tmp_path / "py")
    assert [r["case"] for r in rows] == ["free-body-lgvi-n100", "free-body-lgvi-n200",
                                         "free-body-odeint-rk4-quaternion-n100", "free-body-odeint-rk4-quaternion-n200"]
    # Second order: the final error falls by ~4 per halving of h, for both methods.
    for a, b in ((rows[0], rows[1]), (rows[2], rows[3])):
        assert 3.0 < a["final_error"] / b["final_error"] < 5.0 or a["method"] == "odeint-rk4"
    rk4 = rows[2]["final_error"] / rows[3]["final_error"]
    assert 12.0 < rk4 < 20.0, rk4  # fourth order: 16
    if EXE:
        subprocess.run([EXE, "study", str(study), "--out", str(tmp_path / "cli"), "--no-plots"], check=True,
                       capture_output=True)
        cli = [line for line in open(tmp_path / "cli" / "summary.csv") if not line.startswith("#")]
        header = cli[0].strip().split(",")
        at = header.index("final_error")
        assert [float(line.split(",")[at]) for line in cli[1:]] == [r["final_error"] for r in rows]
    with pytest.raises(ValueError, match="study: no shipped study 'nope'"):
        lgvi.run_study("nope", tmp_path / "x")
    with pytest.raises(ValueError, match="formats: must be png, pdf or svg"):
        lgvi.run_study(str(study), tmp_path / "y", formats="gif")


@harness
def test_run_study_returns_an_ensembles_rows_and_statistics_as_numpy_arrays(tmp_path):
    study = tmp_path / "ens.toml"
    study.write_text('name = "ens"\nscenes = [{ scene = "free-body", horizons = [0.5] }]\n'
                     'methods = ["lgvi", "lgvi-yoshida4"]\nh = [0.05, 0.025]\nreference = "exact"\n'
                     'metrics = ["final-error", "energy"]\nsamples = 5\n'
                     'ensemble = { samples = 5, seed = 3, attitude = "uniform", moments = { range = [0.5, 2.0] }, '
                     'omega = { norm = [1.0, 2.0] } }\n')
    rows = lgvi.run_study(str(study), tmp_path / "py")
    assert len(rows) == 20 and rows[0]["case"] == "free-body-s0-lgvi-h0.05"
    assert rows.samples["sample"].dtype == float
    assert list(rows.samples["sample"][::4]) == [0.0, 1.0, 2.0, 3.0, 4.0]
    assert rows.samples["parameters.inertia[0]"].shape == (20,)
    stats = rows.statistics
    # Per method and step: one entry per metric that some row has.
    error = (stats["metric"] == "final_error")
    labels = list(stats["label"][error])
    assert len(labels) == 4 and labels[0] == labels[1] != labels[2] == labels[3]
    assert [float(h) for h in stats["h"][error]] == [0.05, 0.025, 0.05, 0.025]
    assert (stats["samples"][error] == 5).all() and (stats["count"][error] == 5).all()
    # The quantiles are numpy's default ones of the rows' values.
    first = rows.samples["final_error"][0::4]
    assert stats["median"][error][0] == pytest.approx(np.median(first), rel=1e-15)
    assert stats["q95"][error][0] == pytest.approx(np.quantile(first, 0.95), rel=1e-15)
    assert stats["max"][error][0] == first.max()
    # Sample 2 alone: its rows again, equal bit for bit.
    again = lgvi.run_study(str(study), tmp_path / "one", sample=2)
    assert [r["case"] for r in again] == [r["case"] for r in rows[8:12]]
    assert [r["final_error"] for r in again] == [r["final_error"] for r in rows[8:12]]
    try:
        import pandas  # noqa: F401
    except ImportError:
        assert rows.frame is None
    else:
        assert rows.frame.shape[0] == 20 and rows.statistics_frame.shape[0] == len(stats["metric"])


# --- the CLI's bad options, from Python ---------------------------------------------------------
# Each row: the CLI's arguments, the same call from Python, and the reason both must give (the
# CLI names --option, Python the argument). The CLI exits 1 (bad input) with the reason on stderr.
BAD_OPTIONS = [
    (["simulate", "free-body", "--method", "cvode-bdf", "--model", "quaternion", "--rtol", "2"],
     lambda: lgvi.simulate(lgvi.load_scene("free-body"), method="cvode-bdf", model="quaternion", rtol=2.0),
     r"rtol: must be a number in \[1e-14, 0.1\]"),
    (["simulate", "free-body", "--method", "nonsense"],
     lambda: lgvi.simulate(lgvi.load_scene("free-body"), method="nonsense"), r"nonsense"),
    (["simulate", "free-body", "--h", "-1"], lambda: lgvi.load_scene("free-body", h=-1.0), r"integration\.h"),
    (["simulate", "free-body", "--form", "odd"], lambda: lgvi.load_scene("free-body", form="odd"), r"odd"),
    (["simulate", "bicycle"], lambda: lgvi.load_scene("bicycle"), r"bicycle: unknown scene"),
    (["ocp", "pendulum", "--steps", "100000000"], lambda: lgvi.solve_ocp("pendulum", steps=10**8),
     r"steps: must be an integer in \[1, 1000000\]"),
    (["ocp", "pendulum", "--max-iterations", "0"], lambda: lgvi.solve_ocp("pendulum", max_iterations=0),
     r"max_iterations: must be an integer in \[1, 1000000\]"),
    (["ocp", "pendulum", "--lm-damping", "-1"], lambda: lgvi.solve_ocp("pendulum", lm_damping=-1.0),
     r"lm_damping: must be a number in \(0, 1e10\]"),
    (["ocp", "dumbbell", "--sphere-radius", "0"], lambda: lgvi.solve_ocp("dumbbell", sphere_radius=0.0),
     r"sphere_radius: must be a number in \(0, 1e100\]"),
    (["ocp", "cart-pendulum", "--tolerance", "2"], lambda: lgvi.solve_ocp("cart-pendulum", tolerance=2.0),
     r"tolerance: must be a number in \(0, 0.1\]"),
    (["ocp", "cart-pendulum", "--starts", "0"], lambda: lgvi.solve_ocp("cart-pendulum", starts=0),
     r"starts: must be an integer in \[1, 10000\]"),
    (["ocp", "cart-pendulum", "--knots", "1000000000000"], lambda: lgvi.solve_ocp("cart-pendulum", knots=10**12),
     r"knots: must be an integer in \[3, 1000\]"),
    (["ocp", "cart-pendulum", "--solver", "nope"], lambda: lgvi.solve_ocp("cart-pendulum", solver="nope"),
     r"solver: must be 'slsqp', 'ipopt'"),
    (["ocp", "pendulum", "--knots", "5"], lambda: lgvi.solve_ocp("pendulum", knots=5),
     r"knots: applies to the direct method only"),
    (["ocp", "pendulum", "--weight", "1,2"], lambda: lgvi.solve_ocp("pendulum", W=[1.0, 2.0]),
     r"W: needs 3 values|weight: needs 3 values"),
    (["suite", "default", "--shard", "3/2", "--out", "{tmp}/s"],
     lambda: lgvi.run_suite("default", "/nonexistent/never", shard="3/2"), r"shard"),
    (["suite", "nope", "--out", "{tmp}/s"], lambda: lgvi.run_suite("nope", "/nonexistent/never"), r"nope"),
]


@harness
@pytest.mark.parametrize("argv, call, reason", BAD_OPTIONS, ids=lambda x: " ".join(x) if isinstance(x, list) else "")
def test_the_clis_bad_options_are_refused_alike_from_python(tmp_path, argv, call, reason):
    with pytest.raises(ValueError) as raised:
        call()
    assert re.search(reason, str(raised.value)), str(raised.value)
    if not EXE:
        pytest.skip("LGVI_TESTBED_EXE not set: the CLI half is not run")
    args = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    cli = subprocess.run([EXE] + args, capture_output=True, text=True, timeout=120)
    assert cli.returncode == 1, (args, cli.returncode, cli.stderr)
    cli_reason = re.sub(r"--([a-z-]+)", lambda m: m.group(1).replace("-", "_"), cli.stderr)
    assert re.search(reason.replace("W: needs", "weight: needs"), cli_reason), cli.stderr
