"""The harness functions whose options are written out here in full, so that their signatures,
help() and the type stubs list every option (the compiled function takes them as keywords)."""
import numpy as _np

from . import _lgvi


def solve_ocp(problem: "Union[str, lgvi.Scene]", *, W: "Optional[numpy.typing.ArrayLike]" = None,
              h: "Optional[float]" = None, steps: "Optional[int]" = None, t_final: "Optional[float]" = None,
              form: "Optional[str]" = None, solver: "Optional[str]" = None, max_iterations: "Optional[int]" = None,
              tolerance: "Optional[float]" = None, decomposition: "Optional[bool]" = None,
              merit: "Optional[str]" = None, globalization: "Optional[str]" = None,
              lm_damping: "Optional[float]" = None, nonmonotone_memory: "Optional[int]" = None,
              guess: "Optional[List[float]]" = None, sphere_radius: "Optional[float]" = None,
              knots: "Optional[int]" = None, spline: "Optional[str]" = None, gradients: "Optional[str]" = None,
              starts: "Optional[int]" = None, seed: "Optional[int]" = None, first_start: "Optional[int]" = None,
              hessian: "Optional[str]" = None, state_guess: "Optional[str]" = None,
              shooting_interval: "Optional[int]" = None, intervals: "Optional[int]" = None,
              out: "Optional[os.PathLike]" = None) -> "dict":
    """Optimal control, as `lgvi-testbed ocp PROBLEM`.

    problem: the paper's 'pendulum', 'dumbbell' (indirect shooting), 'cart-pendulum',
    'connected-bodies' (direct method), a scene with an [ocp] table by name or path, or a Scene
    (load_scene, parse_scene, make_scene) with an [ocp] table.

    Overrides (None: the scene's own): W, the control weight, a number per control (its
    diagonal) or the square matrix (symmetric positive definite; the CLI's --weight); h, or steps
    (h = t_final / steps), and t_final, the horizon; form ('symmetric' or 'printed').

    Solver options, the CLI's with underscores and checked against the same ranges (ValueError
    naming the argument): indirect: max_iterations, decomposition, merit, globalization,
    lm_damping, nonmonotone_memory, guess (lambda_0), sphere_radius (dumbbell); direct: solver
    ('slsqp', 'ipopt', 'ddp'), max_iterations (evaluations), tolerance, knots, spline, gradients,
    starts, seed, first_start, hessian, state_guess, shooting_interval; solver='collocation'
    (continuous Hermite-Simpson on the quaternion model, every system with an [ocp] table): intervals,
    tolerance, max_iterations. out: keep the files in this directory (default: a temporary one,
    removed).

    Every summary carries the replayed yardstick: the answer's controls replayed on the
    continuous quaternion model (replayed_cost, replayed_violation, replay_status).

    Returns {summary (the JSON summary; summary['W'] the weight as an (n_u, n_u) array),
    trajectory, history [, knots] (column dicts: {columns, t, R, Omega, ...}), converged, out}.
    """
    given = {key: value for key, value in locals().items() if key != "problem" and value is not None}
    result = _lgvi.solve_ocp(problem, **given)
    weight = result["summary"].get("W")
    if isinstance(weight, list):
        n = int(round(len(weight) ** 0.5))
        result["summary"]["W"] = _np.array(weight, dtype=float).reshape(n, n)
    return result


