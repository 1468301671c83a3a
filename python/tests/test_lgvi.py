"""The Python module lgvi: numpy in and out, conservation, agreement with the C++ CLI, errors.

Run through ctest (python_tests), which sets PYTHONPATH to the build's python/ directory and
LGVI_TESTBED_EXE, LGVI_SOURCE_DIR for the comparison with the CLI.
"""
import io
import os
import stat
import subprocess
import tomllib

import numpy as np
import pytest

import lgvi

EPS = np.finfo(float).eps
J = np.array([0.13, 0.28, 0.17])


def test_so3_exp_log_hat_vee_roundtrip():
    w = np.array([0.3, -1.2, 0.7])
    R = lgvi.so3.exp(w)
    assert R.shape == (3, 3)
    # exp lands on SO(3) and log inverts it (|w| < pi): round-off, a few ulps of O(1) entries.
    assert np.abs(R.T @ R - np.eye(3)).max() < 10 * EPS
    assert np.abs(lgvi.so3.log(R) - w).max() < 100 * EPS
    assert np.abs(lgvi.so3.vee(lgvi.so3.hat(w)) - w).max() == 0.0
    v = np.array([1.0, 2.0, 3.0])
    assert np.allclose(lgvi.so3.hat(w) @ v, np.cross(w, v), rtol=0, atol=10 * EPS)


def test_free_body_conserves_momentum_and_energy():
    body = lgvi.FreeRigidBody(J)
    Omega0 = np.array([0.05, 0.05, 3.0])
    run = lgvi.simulate(body, np.eye(3), Omega0, h=0.005, steps=4000)
    assert run["stats"]["status"] == "completed"
    assert run["t"].shape == (4001,) and run["R"].shape == (4001, 3, 3) and run["Omega"].shape == (4001, 3)
    # Spatial momentum R J Omega is an exact discrete invariant (Noether): round-off only, a few
    # ulps per step accumulated over 4000 steps, |pi| ~ 0.5: 4000 * 8 eps * |pi| ~ 4e-12.
    pi = np.einsum("nij,j,nj->ni", run["R"], J, run["Omega"])
    assert np.abs(pi - pi[0]).max() < 4000 * 8 * EPS * np.linalg.norm(pi[0])
    # Without a potential the LGVI's energy is conserved too (the rotation update preserves
    # |J Omega| and Omega^T J Omega to its residual, 16 eps relative per step).
    E = run["energy"]
    assert np.abs(E - E[0]).max() < 4000 * 16 * EPS * E[0]
    # Every R stays orthonormal to round-off.
    RtR = np.einsum("nki,nkj->nij", run["R"], run["R"])
    assert np.abs(RtR - np.eye(3)).max() < 1e-12


def test_pendulum_energy_error_bounded_and_vertical_momentum_conserved():
    p = lgvi.Pendulum3D.paper()
    Omega0 = np.full(3, 4.14)
    run = lgvi.simulate(p, np.eye(3), Omega0, h=1e-3, steps=5000, every=10)
    assert run["t"].shape == (501,)
    vertical = np.einsum("nj,nj->n", run["R"][:, 2, :], run["Omega"] * p.inertia.diagonal())
    # e3^T R J Omega is an exact invariant of the LGVI (the control-free symmetry): round-off.
    assert np.abs(vertical - vertical[0]).max() < 1e-11
    # Energy error of a second-order symplectic method: O(h^2) times the energy scale. |E| ~ 4,
    # the kinetic energy ~ 5: C h^2 with C ~ |Omega|^2 E ~ 50 gives ~5e-5; a factor 10 of room.
    E = run["energy"]
    assert np.abs(E - E[0]).max() < 5e-4


def test_step_is_simulate_of_one_step():
    p = lgvi.Pendulum3D.paper()
    R0 = lgvi.so3.exp(np.array([0.1, 0.2, -0.3]))
    Omega0 = np.array([1.0, -2.0, 0.5])
    R1, Omega1 = lgvi.step(p, R0, Omega0, 1e-2)
    run = lgvi.simulate(p, R0, Omega0, h=1e-2, steps=1)
    assert np.array_equal(R1, run["R"][1]) and np.array_equal(Omega1, run["Omega"][1])


def read_cli_csv(text):
    """The CLI's CSV: '# key: value' metadata, a header row, rows."""
    lines = [line for line in text.splitlines() if not line.startswith("#")]
    header = lines[0].split(",")
    data = np.loadtxt(io.StringIO("\n".join(lines[1:])), delimiter=",", ndmin=2)
    return {name: data[:, i] for i, name in enumerate(header)}


@pytest.mark.parametrize("scene", ["free-body", "pendulum"])
def test_agrees_with_the_cli(scene):
    """The module and `lgvi-testbed simulate SCENE --out -` run the same flow map on the same
    scene: their rows must be identical (the same doubles, written in round-trip form)."""
    src = os.environ["LGVI_SOURCE_DIR"]
    with open(os.path.join(src, "experiments", "scenes", scene + ".toml"), "rb") as f:
        spec = tomllib.load(f)
    t_final = 2.0
    cli = subprocess.run([os.environ["LGVI_TESTBED_EXE"], "simulate", scene, "--t-final", str(t_final), "--out", "-"],
                         check=True, capture_output=True, text=True)
    csv = read_cli_csv(cli.stdout)
    par, init, integ = spec["parameters"], spec["initial"], spec["integration"]
    if spec["system"] == "free-body":
        system = lgvi.FreeRigidBody(np.array(par["inertia"]))
    else:
        system = lgvi.Pendulum3D(par["mass"], np.array(par["inertia"]), np.array(par["rho"]), par["gravity"])
    h = integ["h"]
    steps = round(t_final / h)
    run = lgvi.simulate(system, np.array(init["R"], dtype=float), np.array(init["Omega"], dtype=float), h=h,
                        steps=steps, form=integ["form"], every=integ["output_every"])
    assert run["t"].shape == csv["t"].shape
    R_cli = np.stack([csv[f"R{i}{j}"] for i in (1, 2, 3) for j in (1, 2, 3)], axis=1).reshape(-1, 3, 3)
    Omega_cli = np.stack([csv[f"Omega{i}"] for i in (1, 2, 3)], axis=1)
    assert np.array_equal(run["R"], R_cli)
    assert np.array_equal(run["Omega"], Omega_cli)


def test_baseline_agrees_with_lgvi_to_its_tolerance():
    body = lgvi.FreeRigidBody(J)
    Omega0 = np.array([0.05, 0.05, 3.0])
    base = lgvi.simulate_baseline(body, np.eye(3), Omega0, t_final=2.0, samples=20, method="odeint-dopri5",
                                  rtol=1e-10)
    assert base["stats"]["status"] == "completed"
    assert base["R"].shape == (21, 3, 3)
    fine = lgvi.simulate(body, np.eye(3), Omega0, h=1e-4, steps=20000, every=1000)
    # The LGVI at h = 1e-4 is second order: error ~ C h^2 t with C ~ |Omega|^3 ~ 30: ~6e-7 at t = 2;
    # the baseline at rtol 1e-10 is far below that. 1e-5 leaves an order of magnitude.
    assert np.abs(base["R"] - fine["R"]).max() < 1e-5
    assert "odeint-dopri5" in lgvi.baseline_methods()


def test_pendulum_transfer_converges():
    res = lgvi.solve_pendulum_transfer(h=0.01)
    s = res["summary"]
    assert s["converged"], s["brief"]
    assert s["violation"] < 1e-12
    assert res["u"].shape == (101, 3) and res["R"].shape == (101, 3, 3)
    # The terminal attitude is the target diag(-1, -1, 1) to the violation.
    assert np.abs(res["R"][-1] - np.diag([-1.0, -1.0, 1.0])).max() < 1e-11


def test_bad_input_raises_value_error_naming_the_argument():
    body = lgvi.FreeRigidBody(J)
    with pytest.raises(ValueError, match=r"R0: expected shape \(3, 3\), got \(3,\)"):
        lgvi.simulate(body, np.ones(3), np.zeros(3), h=0.1, steps=1)
    with pytest.raises(ValueError, match=r"Omega0\[0\]: must be finite \(got nan\)"):
        lgvi.simulate(body, np.eye(3), np.array([np.nan, 0, 0]), h=0.1, steps=1)
    with pytest.raises(ValueError, match="R0: is not a rotation matrix"):
        lgvi.simulate(body, 2 * np.eye(3), np.zeros(3), h=0.1, steps=1)
    with pytest.raises(ValueError, match=r"h: must be > 0 \(got -1\)"):
        lgvi.simulate(body, np.eye(3), np.zeros(3), h=-1.0, steps=1)
    with pytest.raises(ValueError, match="inertia"):
        lgvi.FreeRigidBody(np.array([1.0, 1.0, 5.0]))  # violates the triangle inequality
    with pytest.raises(ValueError, match="method"):
        lgvi.simulate_baseline(body, np.eye(3), np.zeros(3), t_final=1.0, method="no-such-method")
    with pytest.raises(ValueError, match="form"):
        lgvi.simulate(body, np.eye(3), np.zeros(3), h=0.1, steps=1, form="sideways")


def test_cli_streams_to_stdout_fifo_and_refuses_a_directory(tmp_path):
    """--out - pipes into head; an existing FIFO is written in place (still a FIFO after); a
    directory is refused (exit 3, a one-line error naming it)."""
    exe = os.environ["LGVI_TESTBED_EXE"]
    head = subprocess.run(f"'{exe}' simulate pendulum --out - | head -n 3", shell=True, check=True,
                          capture_output=True, text=True)
    assert head.stdout.splitlines() == ["# scene: pendulum", "# scene_file: experiments/scenes/pendulum.toml",
                                        "# system: pendulum"]
    fifo = tmp_path / "rows.fifo"
    os.mkfifo(fifo)
    reader = subprocess.Popen(["cat", str(fifo)], stdout=subprocess.PIPE, text=True)
    subprocess.run([exe, "simulate", "free-body", "--t-final", "0.5", "--out", str(fifo)], check=True,
                   capture_output=True)
    text = reader.communicate(timeout=60)[0]
    assert read_cli_csv(text)["t"][-1] == 0.5
    assert "# status: completed" in text  # the closing metadata, after the rows

    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    refused = subprocess.run([exe, "simulate", "free-body", "--out", str(tmp_path)], capture_output=True, text=True)
    assert refused.returncode == 3
    assert "is a directory" in refused.stderr


# --- the CLI's limits (issue 34, N8) --------------------------------------------------------------
# The module goes through the same checks as the CLI: numbers by the scene files' rule (finite, 0
# or of magnitude in [1e-100, 1e100]), at most 10^12 steps, the adaptive methods' tolerance range
# [1e-14, 0.1] (the solvers' own validation), and at most 10^7 rows returned. Each call below used
# to return NaN/Inf, the initial state as "completed", or run until memory ran out.

BODY = lgvi.FreeRigidBody(J)
I3 = np.eye(3)
W0 = np.array([0.3, 1.0, 0.2])


@pytest.mark.parametrize("call, match", [
    # h giving more steps than any horizon may have: the initial state came back as "completed".
    (lambda: lgvi.simulate_baseline(BODY, I3, W0, t_final=1.0, method="odeint-rk4", h=1e-20),
     r"h: gives too many steps .*limit 1e12"),
    (lambda: lgvi.simulate_baseline(BODY, I3, W0, t_final=1.0, method="odeint-rk4", h=0.0), r"h: must be > 0"),
    (lambda: lgvi.simulate_baseline(BODY, I3, W0, t_final=1.0, method="odeint-rk4", h=np.inf), r"h: must be finite"),
    # tolerances: the CLI's range
    (lambda: lgvi.simulate_baseline(BODY, I3, W0, t_final=1.0, rtol=2.0), r"rtol: must be a number in \[1e-14, 0.1\]"),
    (lambda: lgvi.simulate_baseline(BODY, I3, W0, t_final=1.0, atol=1e-300), r"atol: is below round-off"),
    (lambda: lgvi.simulate_baseline(BODY, I3, W0, t_final=1.0, rtol=np.nan), r"rtol: .*\[1e-14, 0.1\]"),
    # horizon and output
    (lambda: lgvi.simulate_baseline(BODY, I3, W0, t_final=1e300), r"t_final: must be 0 or of magnitude"),
    (lambda: lgvi.simulate_baseline(BODY, I3, W0, t_final=-1.0), r"t_final: must be > 0"),
    (lambda: lgvi.simulate_baseline(BODY, I3, W0, t_final=1.0, samples=10**12), r"samples: .*\[1, 9999999\]"),
    (lambda: lgvi.simulate(BODY, I3, W0, h=0.01, steps=10**13), r"steps: must be an integer in \[0, 1e12\]"),
    (lambda: lgvi.simulate(BODY, I3, W0, h=0.01, steps=10**9), r"every: steps / every give 1000000002 rows; a call returns at most 10000000"),
    (lambda: lgvi.simulate(BODY, I3, W0, h=0.01, steps=10, every=0), r"every: must be an integer in \[1, 1e12\]"),
    (lambda: lgvi.simulate(BODY, I3, W0, h=1e-300, steps=10), r"h: must be 0 or of magnitude"),
    (lambda: lgvi.step(BODY, I3, W0, h=np.nan), r"h: must be finite"),
    # numbers whose products overflow: NaN/Inf energies and states
    (lambda: lgvi.simulate(BODY, I3, np.array([1e200, 0.0, 0.0]), h=0.01, steps=1), r"Omega0\[0\]: .*magnitude"),
    (lambda: lgvi.FreeRigidBody(np.array([1e300, 1e300, 1e300])), r"inertia\[0\]: .*magnitude"),
    (lambda: BODY.energy(I3, np.array([0.0, 1e160, 0.0])), r"Omega\[1\]: .*magnitude"),
    (lambda: lgvi.Pendulum3D(1e300, J, np.array([0, 0, 0.1])), r"mass: .*magnitude"),
    (lambda: lgvi.Pendulum3D(1.0, J, np.array([0, 0, 0.1]), gravity=np.inf), r"gravity: must be finite"),
    (lambda: lgvi.so3.exp(np.array([1e200, 0.0, 0.0])), r"w\[0\]: .*magnitude"),
    # the paper's pendulum transfer: the solver's ranges
    (lambda: lgvi.solve_pendulum_transfer(h=1e-8), r"h: .*between 1 and 1000000"),
    (lambda: lgvi.solve_pendulum_transfer(tolerance=2.0), r"tolerance: must be a number in \(0, 0.1\]"),
    (lambda: lgvi.solve_pendulum_transfer(max_iterations=0), r"max_iterations: must be an integer in \[1, 1000000\]"),
    (lambda: lgvi.solve_pendulum_transfer(initial_multiplier=np.array([1, 1, 1e300, 1, 1, 1.0])),
     r"initial_multiplier\[2\]: .*magnitude"),
])
def test_the_clis_limits_raise_value_error_naming_the_argument(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_the_limits_themselves_are_accepted():
    """The ends of the ranges run: the tolerances 1e-14 and 0.1, a long run with a coarse output."""
    run = lgvi.simulate_baseline(BODY, I3, W0, t_final=1.0, samples=10, rtol=1e-14, atol=1e-14)
    assert run["stats"]["status"] == "completed"
    assert np.isfinite(run["energy"]).all()
    run = lgvi.simulate_baseline(BODY, I3, W0, t_final=1.0, samples=10, rtol=0.1)
    assert run["stats"]["status"] == "completed"
    run = lgvi.simulate(BODY, I3, W0, h=0.01, steps=10**5, every=10**5)
    assert run["t"].shape == (2,)
