"""A potential defined in Python (potential_scene): it runs with the LGVI, a baseline and a Lie
group method exactly as the built-in potential it restates, and a callable that fails stops the
run with CallbackError naming it and where the run stopped.

Run through ctest (python_tests)."""
import numpy as np
import pytest

import lgvi

pytestmark = pytest.mark.skipif(not lgvi.has_harness, reason="the module was built without the harness")

# The shipped magnetic-dipole scene's body and field (experiments/scenes/magnetic-dipole.toml).
DIPOLE = np.array([0.0, 0.0, 2.0])
FIELD = np.array([0.05, 0.0, 0.1])
INERTIA = [0.13, 0.28, 0.17]
OMEGA0 = [0.5, 1.0, 3.0]


def dipole_potential(R):
    return -FIELD @ R @ DIPOLE


def dipole_moment(R):
    return np.cross(DIPOLE, R.T @ FIELD)


def python_dipole(**overrides):
    options = dict(h=0.005, t_final=1.0, output_every=10)
    options.update(overrides)
    return lgvi.potential_scene(INERTIA, dipole_potential, dipole_moment, {"Omega": OMEGA0}, **options)


def builtin_dipole():
    return lgvi.load_scene("magnetic-dipole", t_final=1.0)


@pytest.mark.parametrize("method, model", [("lgvi", None), ("lgvi-yoshida4", None), ("odeint-rk4", "quaternion"),
                                           ("gsl-rk8pd", "quaternion"), ("rkmk4", None), ("splitting-dlm", None)])
def test_a_python_dipole_runs_as_the_builtin_one(method, model):
    """Same method, same step: the trajectories agree to rounding. The callables' arithmetic
    (numpy) differs from Eigen's by an ulp per evaluation; over 200 steps of a tumbling body
    (energy 1.6 J, |Omega| ~ 3 rad/s, no exponential divergence at t = 1 s) that stays below
    1e-12 in R and Omega; gated at 1e-10."""
    names = [m["name"] for m in lgvi.methods()]
    if method not in names:
        pytest.skip(f"{method} is not registered")
    kwargs = {"model": model} if model else {}
    if method == "gsl-rk8pd":
        kwargs.update(rtol=1e-10, atol=1e-10)
    mine = lgvi.simulate(python_dipole(), method=method, **kwargs)
    theirs = lgvi.simulate(builtin_dipole(), method=method, **kwargs)
    assert mine["summary"]["status"] == "completed", mine["summary"]["status_detail"]
    assert mine["R"].shape == theirs["R"].shape
    assert np.abs(mine["R"] - theirs["R"]).max() < 1e-10
    assert np.abs(mine["Omega"] - theirs["Omega"]).max() < 1e-10
    assert mine["summary"]["max_energy_error"] == pytest.approx(theirs["summary"]["max_energy_error"], rel=1e-3, abs=1e-13)


def test_the_lgvi_calls_the_potential_once_per_step():
    """One moment evaluation per LGVI step (a step's end kick is the next step's start kick),
    counted by the callable itself: the first step's start kick adds one. The cost of a step is
    that of one Python call plus the step."""
    calls = []

    def counting_moment(R):
        calls.append(1)
        return dipole_moment(R)

    scene = lgvi.potential_scene(INERTIA, dipole_potential, counting_moment, {"Omega": OMEGA0}, h=0.01, t_final=1.0)
    calls.clear()  # the check at the initial attitude
    run = lgvi.simulate(scene)
    assert run["summary"]["potential_evaluations"] == 100
    assert len(calls) == 101


def test_a_failing_callable_stops_the_run_and_is_named():
    def moment_raises_late(R):
        if R[0, 1] > 0.5:  # the body turns past this within the horizon
            raise ZeroDivisionError("deliberately")
        return dipole_moment(R)

    scene = lgvi.potential_scene(INERTIA, dipole_potential, moment_raises_late, {"Omega": OMEGA0}, h=0.01,
                                 t_final=5.0)
    with pytest.raises(lgvi.CallbackError, match=r"moment\(R\) raised ZeroDivisionError: deliberately; the run "
                                                 r"stopped: .*step") as raised:
        lgvi.simulate(scene)
    assert isinstance(raised.value.__cause__, ZeroDivisionError)
    # The same scene runs again (the record is cleared) and fails the same way.
    with pytest.raises(lgvi.CallbackError):
        lgvi.simulate(scene, method="odeint-rk4", model="quaternion")

    shapes = {"a (2,) array": lambda R: np.ones(2), "a string": lambda R: "abc", "None": lambda R: None}
    for what, bad in shapes.items():
        with pytest.raises(ValueError, match=r"moment\(R\) returned .* \(expected 3 floats\) \(at the initial state"):
            lgvi.potential_scene(INERTIA, dipole_potential, bad, h=0.01, t_final=1.0)
    with pytest.raises(ValueError, match=r"potential\(R\) returned a non-finite value"):
        lgvi.potential_scene(INERTIA, lambda R: float("nan"), dipole_moment, h=0.01, t_final=1.0)
    with pytest.raises(ValueError, match=r"potential\(R\) returned \[1.0, 2.0\] \(expected a float\)"):
        lgvi.potential_scene(INERTIA, lambda R: [1.0, 2.0], dipole_moment, h=0.01, t_final=1.0)
    with pytest.raises(TypeError, match="moment: expected a callable"):
        lgvi.potential_scene(INERTIA, dipole_potential, 3.0, h=0.01, t_final=1.0)
    with pytest.raises(ValueError, match="parameters.inertia"):
        lgvi.potential_scene([1.0, 2.0, 5.0], dipole_potential, dipole_moment, h=0.01, t_final=1.0)

    def nan_later(R):
        return dipole_moment(R) if R[0, 1] <= 0.5 else np.array([np.nan, 0.0, 0.0])

    scene = lgvi.potential_scene(INERTIA, dipole_potential, nan_later, {"Omega": OMEGA0}, h=0.01, t_final=5.0)
    with pytest.raises(lgvi.CallbackError, match=r"moment\(R\) returned a non-finite value; the run stopped"):
        lgvi.simulate(scene)


def pd_torque(target, kp, kd):
    """The scenes' PD law (experiments/input/controls.hpp) written in Python."""
    def torque(t, R, Omega):
        E = target.T @ R
        skew = 0.5 * (E - E.T)
        return -kp * np.array([skew[2, 1], skew[0, 2], skew[1, 0]]) - kd * Omega
    return torque


@pytest.mark.parametrize("method, model", [("lgvi", None), ("lgvi-yoshida4", None), ("odeint-rk4", "quaternion")])
def test_a_python_torque_acts_as_the_scenes_own_control(method, model):
    """torque(t, R, Omega) enters as the scene's PD feedback does (the LGVI's impulses at both ends
    of each step, the baselines' right-hand side): the PD law written in Python reproduces the
    [control] type = "pd" run, and a torque of t alone the sinusoid [control] run, to rounding
    (the same discrete equations, the law's arithmetic in numpy: ~1e-15 per evaluation; gated
    at 1e-10 over 200 steps)."""
    kwargs = {"model": model} if model else {}
    target = lgvi.so3.exp(np.array([0.3, -0.2, 0.5]))
    options = dict(h=0.005, t_final=1.0, output_every=10)
    mine = lgvi.potential_scene(INERTIA, dipole_potential, dipole_moment, {"Omega": OMEGA0},
                                torque=pd_torque(target, 2.0, 0.3), **options)
    theirs = lgvi.potential_scene(INERTIA, dipole_potential, dipole_moment, {"Omega": OMEGA0},
                                  control={"type": "pd", "target": target, "kp": 2.0, "kd": 0.3}, **options)
    a, b = lgvi.simulate(mine, method=method, **kwargs), lgvi.simulate(theirs, method=method, **kwargs)
    assert a["summary"]["status"] == "completed", a["summary"]["status_detail"]
    assert np.abs(a["R"] - b["R"]).max() < 1e-10 and np.abs(a["Omega"] - b["Omega"]).max() < 1e-10

    amplitude, frequency = np.array([0.2, 0.0, -0.1]), np.array([1.5, 0.0, 0.5])
    timed = lgvi.potential_scene(INERTIA, dipole_potential, dipole_moment, {"Omega": OMEGA0},
                                 torque=lambda t, R, Omega: amplitude * np.sin(2 * np.pi * frequency * t), **options)
    sinusoid = lgvi.potential_scene(INERTIA, dipole_potential, dipole_moment, {"Omega": OMEGA0},
                                    control={"type": "sinusoid", "amplitude": amplitude, "frequency": frequency},
                                    **options)
    a, b = lgvi.simulate(timed, method=method, **kwargs), lgvi.simulate(sinusoid, method=method, **kwargs)
    assert np.abs(a["R"] - b["R"]).max() < 1e-10 and np.abs(a["Omega"] - b["Omega"]).max() < 1e-10


def test_a_failing_torque_is_named():
    def late(t, R, Omega):
        if t > 0.5:
            return np.zeros(4)
        return np.zeros(3)

    scene = lgvi.potential_scene(INERTIA, dipole_potential, dipole_moment, {"Omega": OMEGA0}, torque=late, h=0.01,
                                 t_final=1.0)
    with pytest.raises(lgvi.CallbackError, match=r"torque\(t, R, Omega\) returned array\(\[0\., 0\., 0\., 0\.\]\) "
                                                 r"\(expected 3 floats\); the run stopped: .*step 5"):
        lgvi.simulate(scene)
    with pytest.raises(TypeError, match="torque: expected a callable"):
        lgvi.potential_scene(INERTIA, dipole_potential, dipole_moment, torque=1.0, h=0.01, t_final=1.0)
    with pytest.raises(ValueError, match="torque: give torque or control, not both"):
        lgvi.potential_scene(INERTIA, dipole_potential, dipole_moment, torque=late, control={"type": "constant",
                             "value": [0, 0, 0]}, h=0.01, t_final=1.0)


# --- a body with translation (mass and force): the potential-body-se3 system ---------------------

# The shipped anchored-spring scene's body (experiments/scenes/anchored-spring.toml).
SPRING_MASS, SPRING_K = 1.0, 20.0
SPRING_INERTIA = [0.02, 0.03, 0.04]
ANCHOR, ATTACHMENT = np.zeros(3), np.array([0.0, 0.0, 0.1])
SPRING_INITIAL = {"Omega": [1.0, -0.5, 2.0], "x": [0.3, 0.0, 0.0], "v": [0.0, 0.8, 0.2]}


def spring_stretch(R, x):
    return x + R @ ATTACHMENT - ANCHOR


def spring_potential(R, x):
    d = spring_stretch(R, x)
    return 0.5 * SPRING_K * d @ d


def spring_force(R, x):
    return -SPRING_K * spring_stretch(R, x)


def spring_moment(R, x):
    return np.cross(ATTACHMENT, R.T @ spring_force(R, x))


def python_spring(**overrides):
    options = dict(h=0.002, t_final=0.5, output_every=10)
    options.update(overrides)
    return lgvi.potential_scene(SPRING_INERTIA, spring_potential, spring_moment, SPRING_INITIAL, mass=SPRING_MASS,
                                force=spring_force, **options)


@pytest.mark.parametrize("method, model", [("lgvi", None), ("lgvi-yoshida4", None), ("odeint-rk4", "quaternion"),
                                           ("gsl-rk8pd", "quaternion"), ("cvode-bdf", "matrix"), ("rkmk4", None),
                                           ("splitting-dlm", None)])
def test_a_python_spring_body_runs_as_the_builtin_one(method, model):
    """A body with translation defined in Python runs as the built-in anchored spring it restates,
    under the LGVI on SE(3), a composition, baselines on two charts, a Lie group method and a
    splitting: the trajectories agree to rounding (numpy against Eigen, an ulp per evaluation,
    250 steps of a body whose energy is 1.4 J and rates ~2 rad/s, no exponential divergence in
    0.5 s: below 1e-12; gated at 1e-10; the adaptive solvers take the same steps from the same
    values)."""
    names = [m["name"] for m in lgvi.methods()]
    if method not in names:
        pytest.skip(f"{method} is not registered")
    kwargs = {"model": model} if model else {}
    if method in ("gsl-rk8pd", "cvode-bdf"):
        kwargs.update(rtol=1e-10, atol=1e-10)
    mine = lgvi.simulate(python_spring(), method=method, **kwargs)
    theirs = lgvi.simulate(lgvi.load_scene("anchored-spring", t_final=0.5), method=method, **kwargs)
    assert mine["summary"]["status"] == "completed", mine["summary"]["status_detail"]
    assert mine["summary"]["system"] == "potential-body-se3"
    for key in ("R", "Omega", "x", "v"):
        assert mine[key].shape == theirs[key].shape, key
        assert np.abs(mine[key] - theirs[key]).max() < 1e-10, key


def test_the_se3_lgvi_evaluates_the_wrench_once_per_step():
    """force and moment: one call each per LGVI step (plus the first step's start kick)."""
    calls = []

    def counting_force(R, x):
        calls.append(1)
        return spring_force(R, x)

    scene = lgvi.potential_scene(SPRING_INERTIA, spring_potential, spring_moment, SPRING_INITIAL, mass=SPRING_MASS,
                                 force=counting_force, h=0.01, t_final=1.0)
    calls.clear()  # the check at the initial state
    run = lgvi.simulate(scene)
    assert run["summary"]["potential_evaluations"] == 100
    assert len(calls) == 101


def test_a_python_body_with_translation_takes_the_dumbbells_controls():
    """control={'force': ..., 'moment': ...}: a constant force on a body in no potential moves its
    mass centre on the parabola x0 + v0 t + F t^2 / (2 m), which the symmetric LGVI's translation
    (velocity Verlet on a constant force) follows to rounding (t <= 1, |x| <= 3: 1e-12)."""
    zero = np.zeros(3)
    F, m = np.array([0.5, -1.0, 2.0]), 0.8
    scene = lgvi.potential_scene(SPRING_INERTIA, lambda R, x: 0.0, lambda R, x: zero, {"v": [1.0, 0.0, 0.0]},
                                 mass=m, force=lambda R, x: zero, h=0.01, t_final=1.0,
                                 control={"force": {"type": "constant", "value": F}})
    run = lgvi.simulate(scene)
    t = run["t"][:, None]
    expected = np.array([1.0, 0.0, 0.0]) * t + F / (2 * m) * t**2
    assert np.abs(run["x"] - expected).max() < 1e-12


def test_a_failing_callable_of_a_body_with_translation_is_named():
    def force_late(R, x):
        if np.linalg.norm(x) < 0.2:  # the body swings inside this within the horizon
            return np.ones(2)
        return spring_force(R, x)

    scene = lgvi.potential_scene(SPRING_INERTIA, spring_potential, spring_moment, SPRING_INITIAL, mass=SPRING_MASS,
                                 force=force_late, h=0.002, t_final=2.0)
    with pytest.raises(lgvi.CallbackError, match=r"force\(R, x\) returned array\(\[1\., 1\.\]\) \(expected 3 floats\); "
                                                 r"the run stopped: .*step"):
        lgvi.simulate(scene)
    with pytest.raises(ValueError, match=r"moment\(R, x\) returned a non-finite value \(at the initial state"):
        lgvi.potential_scene(SPRING_INERTIA, spring_potential, lambda R, x: np.full(3, np.inf), mass=1.0,
                             force=spring_force, h=0.01, t_final=1.0)
    with pytest.raises(ValueError, match=r"mass: is required with force"):
        lgvi.potential_scene(SPRING_INERTIA, spring_potential, spring_moment, force=spring_force, h=0.01, t_final=1.0)
    with pytest.raises(TypeError, match=r"force: expected a callable f\(R, x\)"):
        lgvi.potential_scene(SPRING_INERTIA, spring_potential, spring_moment, mass=1.0, h=0.01, t_final=1.0)
    with pytest.raises(ValueError, match=r"parameters.mass"):
        lgvi.potential_scene(SPRING_INERTIA, spring_potential, spring_moment, mass=-1.0, force=spring_force, h=0.01,
                             t_final=1.0)
    with pytest.raises(ValueError, match=r"torque: a feedback law u\(t, R, Omega\) is for the body without translation"):
        lgvi.potential_scene(SPRING_INERTIA, spring_potential, spring_moment, mass=1.0, force=spring_force,
                             torque=lambda t, R, Omega: np.zeros(3), h=0.01, t_final=1.0)


# --- the heavy body: a Python pendulum against the built-in one, under every method -------------

PENDULUM_MASS, PENDULUM_G, PENDULUM_RHO = 1.0, 9.81, np.array([0.0, 0.0, 0.3])  # experiments/scenes/pendulum.toml
E3 = np.array([0.0, 0.0, 1.0])


def methods_taking(*systems):
    """The registered methods whose traits list every one of `systems` (an empty list: any system)."""
    return [m["name"] for m in lgvi.methods()
            if not m["traits"]["systems"] or all(s in m["traits"]["systems"] for s in systems)]


# cvode-bdf-projected projects onto the system's own first integrals: the pendulum's energy and
# vertical momentum, a user potential's energy alone. On the two systems it is two methods.
@pytest.mark.parametrize("method", [m for m in methods_taking("pendulum", "potential-body") if m != "cvode-bdf-projected"])
def test_a_python_pendulum_runs_every_method_as_the_builtin_one(method):
    """The paper's 3D pendulum (section 3.2), U(R) = -m g e3^T R rho and M(R) = m g rho x R^T e3
    (eq. 13), written with numpy: every method that takes both systems gives the built-in
    pendulum's trajectory to rounding (an ulp per evaluation from numpy against Eigen, 500 steps
    of the tumbling pendulum, |Omega| ~ 7 rad/s: 1e-12 at most; gated at 1e-10; the adaptive
    solvers take the same steps from the same values)."""
    options = dict(h=1e-3, t_final=0.5, output_every=50)
    mine = lgvi.potential_scene([0.13, 0.28, 0.17], lambda R: -PENDULUM_MASS * PENDULUM_G * E3 @ R @ PENDULUM_RHO,
                                lambda R: PENDULUM_MASS * PENDULUM_G * np.cross(PENDULUM_RHO, R.T @ E3),
                                {"Omega": [4.14, 4.14, 4.14]}, **options)
    theirs = lgvi.load_scene("pendulum", **options)
    a, b = lgvi.simulate(mine, method=method), lgvi.simulate(theirs, method=method)
    assert a["summary"]["status"] == b["summary"]["status"], a["summary"]["status_detail"]
    assert a["R"].shape == b["R"].shape
    assert np.abs(a["R"] - b["R"]).max() < 1e-10 and np.abs(a["Omega"] - b["Omega"]).max() < 1e-10
