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
    tolerance, max_iterations, hessian ('exact', the default; 'limited-memory'; 'cost'). out: keep
    the files in this directory (default: a temporary one, removed).

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




class _StudyRows(list):
    """run_study's result: the summary's rows (a list of dicts, in case order) with the same as
    columns and, for a study with an [ensemble], the statistics over its samples."""

    def __init__(self, rows, statistics):
        super().__init__(rows)
        #: Every summary column as a numpy array, one entry per row (per sample and case): float
        #: where every cell is a number or missing (NaN), else str ("" where missing).
        self.samples = _columns(rows)
        #: The statistics over the samples (study_statistics: NAME-statistics.csv's columns) as
        #: numpy arrays; every array empty for a study without [ensemble].
        self.statistics = {key: _np.asarray(values) if values else _np.array([], dtype=float)
                           for key, values in statistics.items()}
        #: pandas DataFrames of the two, when pandas can be imported (else None).
        self.frame = None
        self.statistics_frame = None
        try:
            import pandas
        except ImportError:
            return
        self.frame = pandas.DataFrame(self.samples)
        self.statistics_frame = pandas.DataFrame(self.statistics)


def _columns(rows):
    """{column: numpy array} of a list of dicts (the union of their keys, first-appearance order)."""
    keys = []
    for row in rows:
        keys += [key for key in row if key not in keys]
    columns = {}
    for key in keys:
        cells = [row.get(key) for row in rows]
        if all(cell is None or (isinstance(cell, (int, float)) and not isinstance(cell, bool)) for cell in cells):
            columns[key] = _np.array([_np.nan if cell is None else float(cell) for cell in cells], dtype=float)
        else:
            columns[key] = _np.array(["" if cell is None else str(cell) for cell in cells], dtype=str)
    return columns


def run_study(study: "str", out: "os.PathLike", quick: "bool" = True, jobs: "int" = 1, shard: "Optional[str]" = None,
              plots: "bool" = False, formats: "Optional[str]" = None, scenes_dir: "Optional[os.PathLike]" = None,
              progress: "bool" = False, sample: "Optional[int]" = None) -> "list":
    """Runs a study into the directory `out`, as `lgvi-testbed study FILE --out OUT`.

    study: a path, or a shipped study's name (data_dirs()['studies']). quick: the study's [quick]
    table; shard: 'i/N'; plots: draw the figures and tables (formats 'png', 'pdf', 'svg' or a list
    'png,pdf'); progress: print the progress lines to stderr afterwards; sample: a study with an
    [ensemble]: only sample K (`--sample K`), drawn exactly as in the whole run.

    Returns the summary's rows (summary.jsonl) as a list of dicts in case order, which also has
    .samples: every column as a numpy array (one entry per row: per sample and case; float where
    every cell is a number, NaN where missing); .statistics: for a study with an [ensemble], the
    statistics over the samples per group, method and setting (median, q05, q25, q75, q95, max,
    failures; study_statistics) as numpy arrays, empty otherwise; .frame and .statistics_frame:
    the same as pandas DataFrames when pandas can be imported (else None).
    """
    rows = _lgvi.run_study(study, out, quick=quick, jobs=jobs, shard=shard, plots=plots, formats=formats,
                           scenes_dir=scenes_dir, progress=progress, sample=sample)
    ensemble = any("sample" in row for row in rows)
    statistics = _lgvi.study_statistics(out) if ensemble and shard is None else {}
    return _StudyRows(rows, statistics)
