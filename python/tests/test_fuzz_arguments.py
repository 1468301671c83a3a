"""Seeded, bounded fuzz of the argument converters of the Python module lgvi.

Property: every public function of lgvi that takes numbers, arrays, strings, dicts or paths is
called with hostile values mixed with valid ones (nan, +-inf, 0, -0.0, subnormals, 1e308, -1,
integers past 64 bits, bools, None, numpy scalars; arrays of the wrong shape, dtype (float32,
int, bool, complex, object, str, datetime) or layout (non-contiguous, Fortran, big-endian,
read-only); ragged and nested lists; empty, NUL, non-ASCII and very long strings; dicts with
unknown or non-string keys; missing, unreadable and special paths; TOML text mutated). Each
call must either
  - return a result whose numbers are all finite (every float, and every float array by
    numpy.isfinite, recursively through dicts, lists, tuples and the returned objects'
    numeric attributes), or
  - raise ValueError or TypeError (pybind11's conversion failure); OSError only from a call
    given a path to write to (simulate csv=, run_suite out=, solve_ocp out=), which may name
    an unwritable path,
and never another exception type, a crash, or a hang. A run that stops early reports it in a
status (stats.status, summary.status) and still returns finite numbers up to where it stopped;
the numbers its status stands for instead are exempt: solve_pendulum_transfer's summary cost
and violation (inf when it reports converged=False), solve_ocp's summary fields of a run that
did not converge; and the harness simulate's summary statistics that have no value (NaN; the
CLI's JSON writes them as null): energy_drift_rate_stderr of a run with at most 2 rows,
max_energy_error_relative when the initial energy is 0.

Bounded: step counts, horizons, sample counts, iteration limits and suites are drawn either
invalid or small (a valid call takes milliseconds), and a call over CALL_SECONDS fails the test;
faulthandler ends the process with every thread's traceback after HANG_SECONDS in one test.

Seed: SEED below; each test draws from random.Random(f"{SEED}:{test name}"), so a run makes the
same calls in the same order every time. About 3300 calls in all (CALLS per test). Time: about
6 s with the GCC build (2 cores, `python3 -m pytest -q python/tests/test_fuzz_arguments.py`),
about 3x that under AddressSanitizer.

Defects this fuzz found, each fixed: its reproducer is in REPRODUCERS (test_reproducers asserts
the fixed behaviour), and the loops draw those arguments too.
"""
import collections
import faulthandler
import math
import os
import random
import time
import warnings

import numpy as np
import pytest

import lgvi

SEED = 20240934
CALL_SECONDS = 10.0  # a hang detector, not a timing test: valid calls here take milliseconds
HANG_SECONDS = 300.0

NAN = float("nan")
INF = float("inf")

# Scalars for any numeric argument: invalid for the module's rules or of the wrong type, and a
# few valid ones of unusual types. Kept free of valid large magnitudes (1e19 is valid: 2**63 is
# in HUGE_INTS) so that a draw never makes a valid call long.
HOSTILE_SCALARS = [
    NAN, INF, -INF, 0, 0.0, -0.0, 1e-320, 5e-324, 1e308, -1e308, -1, -1.0, 1e-101, 1e101, 2**1024, -(2**1024),
    np.float32("nan"), np.float64(-np.inf), np.int64(-1), np.float16(6e-8), np.longdouble("1e4000"),
    None, "", "1", "nan", "\0", b"1", 1 + 2j, np.complex128(1), [1.0], (1.0,), {}, np.array(0.1), np.zeros(2),
    object(),
]
HUGE_INTS = [2**63, 2**64, -(2**63) - 1, 2**63 - 1, -(2**63), np.uint64(2**64 - 1)]

HOSTILE_STRINGS = [
    "", " ", "\0", "symmetric\0", "\0symmetric", "é", "ÿ", "\u2028", "\ud800", "\udcff", "\x7f", "💥", "-", "--help",
    "../", "/", ".", "%s%n{}", "\n", "nan", "a" * 100_000, "SYMMETRIC", " printed", b"\xff", b"symmetric", None, 0,
    1.5, ["symmetric"], {"symmetric": 1},
]

# Entries of an array argument.
ENTRIES = [NAN, INF, -INF, 0.0, -0.0, 1e-320, 5e-324, 1e308, -1.0, 1e-100, 1e100, 1e-101, 1e101, 2**63, 2**64,
           -(2**63) - 1, 2**1024, True, None, "1", "x", 1 + 1j, 0.5, -2.0]

J = np.array([0.13, 0.28, 0.17])


def rotation(w):
    """exp(hat(w)), Rodrigues' formula, in numpy (not through the module under test)."""
    w = np.asarray(w, dtype=float)
    a = np.linalg.norm(w)
    W = np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])
    if a == 0.0:
        return np.eye(3)
    return np.eye(3) + math.sin(a) / a * W + (1.0 - math.cos(a)) / a**2 * W @ W


# --- the property -----------------------------------------------------------------------------------


def describe(x, depth=0):
    """A short reproducible text of an argument (arrays with dtype and shape, long strings cut)."""
    if isinstance(x, np.ndarray):
        flags = "" if x.flags.c_contiguous else ", non-contiguous"
        body = np.array2string(x.ravel()[:12], threshold=12) if x.size and x.dtype.kind != "O" else repr(x.tolist())[:80]
        return f"array({body}, dtype={x.dtype}, shape={x.shape}{flags})"
    if isinstance(x, (str, bytes)) and len(x) > 60:
        return f"{x[:20]!r}*{len(x)}"
    if isinstance(x, dict) and depth < 3:
        return "{" + ", ".join(f"{describe(k, depth + 1)}: {describe(v, depth + 1)}" for k, v in x.items()) + "}"
    if isinstance(x, (list, tuple)) and depth < 3:
        return ("[%s]" if isinstance(x, list) else "(%s)") % ", ".join(describe(v, depth + 1) for v in x[:12])
    text = repr(x)
    return text if len(text) <= 120 else text[:120] + "..."


def non_finite(x, path="result", seen=None):
    """The paths of the non-finite numbers in a result."""
    out = []
    if isinstance(x, (bool, int, str, bytes, type(None), np.bool_, np.integer)):
        return out
    if isinstance(x, (float, np.floating)):
        return [] if math.isfinite(x) else [f"{path} = {x}"]
    if isinstance(x, np.ndarray):
        if x.dtype.kind in "fc":
            bad = ~np.isfinite(x)
            if bad.any():
                out.append(f"{path}: {int(bad.sum())} of {x.size} entries non-finite, first at "
                           f"{tuple(int(i) for i in np.argwhere(bad)[0])}")
        elif x.dtype.kind == "O":
            for i, v in enumerate(x.ravel()):
                out += non_finite(v, f"{path}.flat[{i}]")
        return out
    if isinstance(x, dict):
        for k, v in x.items():
            out += non_finite(v, f"{path}[{k!r}]")
        return out
    if isinstance(x, (list, tuple)):
        for i, v in enumerate(x):
            out += non_finite(v, f"{path}[{i}]")
        return out
    if isinstance(x, os.PathLike):
        return out
    if isinstance(x, lgvi.Scene):
        return non_finite({"h": x.h, "t_final": x.t_final}, path)
    if isinstance(x, lgvi.FreeRigidBody):
        return non_finite({"inertia": x.inertia}, path)
    if isinstance(x, lgvi.Pendulum3D):
        return non_finite({"mass": x.mass, "gravity": x.gravity, "inertia": x.inertia, "rho": x.rho}, path)
    return [f"{path}: unexpected type {type(x).__name__}"]


class Fuzz:
    """One test's random draws and the calls it checks; collects every violation."""

    def __init__(self, name):
        self.rng = random.Random(f"{SEED}:{name}")
        self.calls = 0
        self.failures = []
        self.outcomes = collections.Counter()  # per function: returned, ValueError, TypeError, OSError
        self.rate = 0.5

    def next(self):
        """A new call: the chance that each argument is drawn hostile. A quarter of the calls are
        all valid, so the valid paths (runs, results) are exercised as much as the refusals."""
        self.rate = self.pick([0.0, 0.0, 0.05, 0.15, 0.3, 0.6])

    # -- drawing --
    def pick(self, seq):
        return seq[self.rng.randrange(len(seq))]

    def chance(self, p):
        return self.rng.random() < p

    def valid(self, p_valid):
        return self.chance(1.0 - self.rate if p_valid is None else p_valid)

    def scalar(self, valid, p_valid=None, huge=False, extra=()):
        """A valid value, or a hostile one (HUGE_INTS only if `huge`: they are valid magnitudes)."""
        if self.valid(p_valid):
            return self.pick(valid)
        return self.pick(HOSTILE_SCALARS + list(extra) + (HUGE_INTS if huge else []))

    def string(self, valid, p_valid=None):
        return self.pick(valid) if self.valid(p_valid) else self.pick(HOSTILE_STRINGS)

    def integer(self, valid, invalid=(), p_valid=None):
        """A count: valid small values, or invalid ones (never a valid large count)."""
        if self.valid(p_valid):
            return self.pick(valid)
        return self.pick([-1, -(2**63), 2**63, 2**64, -(2**63) - 1, 1.5, 2.0, NAN, None, "3", b"3", [3], np.float64(2.0),
                          np.array([2]), object()] + list(invalid))

    def array(self, valid, entries=ENTRIES, p_valid=None):
        """`valid` (a float ndarray of the wanted shape) as is, in another layout or dtype, or spoiled."""
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")  # the casts below overflow on purpose
            return self._array(valid, entries, p_valid)

    def _array(self, valid, entries, p_valid):
        rng = self.rng
        v = np.array(valid, dtype=float)
        if self.valid(p_valid):
            form = rng.randrange(20)
            if form == 0:
                return v
            if form == 1:
                return v.tolist()
            if form == 2:  # non-contiguous: every other entry of a larger array
                big = np.zeros(tuple(2 * n for n in v.shape))
                view = big[tuple(slice(None, None, 2) for _ in v.shape)]
                view[...] = v
                return view
            if form == 3:
                return np.asfortranarray(v) if v.ndim == 2 else v[::-1].copy()[::-1]
            if form == 4:
                return v.astype(np.float32)
            if form == 5:
                return v.astype(">f8")
            if form == 6:
                r = v.copy()
                r.flags.writeable = False
                return r
            if form == 7:
                return tuple(map(tuple, v)) if v.ndim == 2 else tuple(v)
            if form == 8:
                return v.astype(np.longdouble)
            if form == 9:
                return np.round(v).astype(np.int64) if rng.random() < 0.5 else v.astype(object)
            return v
        kind = rng.randrange(8)
        if kind <= 2:  # valid shape, some entries hostile
            lst = v.tolist()
            for _ in range(1 + rng.randrange(2 if kind < 2 else v.size)):
                if v.ndim == 1:
                    lst[rng.randrange(len(lst))] = self.pick(entries)
                else:
                    lst[rng.randrange(len(lst))][rng.randrange(len(lst[0]))] = self.pick(entries)
            return lst if rng.random() < 0.5 else np.array(lst, dtype=object)
        if kind == 3:  # valid shape, hostile entries of one numpy dtype
            x = self.pick([e for e in entries if isinstance(e, float)])
            return np.full(v.shape, x, dtype=self.pick([float, np.float32, np.float16]))
        if kind == 4:  # wrong shape
            shape = self.pick([(0,), (1,), (2,), (4,), (6,), (9,), (3,), (3, 3), (1, 3), (3, 1), (3, 3, 1), (0, 3), (),
                               (2, 2), (3, 3, 3), (100_000,)])
            if shape == v.shape:
                shape = (v.size + 1,)
            return np.full(shape, 0.5)
        if kind == 5:  # wrong dtype
            return self.pick([
                v.astype(complex) + 1j, np.full(v.shape, None, dtype=object), v.astype(str), np.full(v.shape, "x"),
                v.astype(bool), np.zeros(v.shape, dtype="datetime64[s]"), np.zeros(v.shape, dtype="timedelta64[s]"),
                np.zeros(v.shape, dtype=[("a", float)]), np.full(v.shape, 1e5).astype(np.float16), v.astype(np.uint64) + 2**63,
                np.zeros(v.shape, dtype=np.int8) - 1, np.array(v.tolist(), dtype=object) + 0j,
            ])
        if kind == 6:  # ragged or nested lists
            lst = v.tolist()
            return self.pick([[lst], lst[:-1] + [[lst[-1]]], [*lst, lst], [[]], [], [[1.0, 2.0], [3.0]], [lst, None],
                              [1.0, [2.0], 3.0], [[[0.5]] * 3] * 3, [{}] * v.size, ["1", "2", "3"][: len(lst)]])
        return self.pick([None, "abc", "", b"\x00\x01", 5, 1.5, True, NAN, {}, {1: 2}, {"R": 1}, set(), frozenset({1.0}),
                          range(3), iter([1.0, 2.0, 3.0]), object(), lgvi, np.float64(1.0), np.array(1.0),
                          memoryview(b"\x00\x01\x02")])

    def vec3(self, valid=None, entries=ENTRIES, scale=2.0):
        if valid is None:
            valid = [self.rng.uniform(-scale, scale) for _ in range(3)]
        return self.array(valid, entries)

    def rot(self, entries=ENTRIES):
        """A rotation (in some layout), a near-rotation, a non-rotation, or a spoiled array."""
        R = rotation([self.rng.uniform(-3, 3) for _ in range(3)])
        if self.chance(self.rate * 0.4):
            return self.pick([2 * R, -R, R + 1e-6, R.T @ np.diag([1, 1, -1]), np.zeros((3, 3)), R.T, R[:, ::-1],
                              R.astype(np.float32), np.eye(3) + 1e-320, R * (1 + 1e-15)])
        return self.array(R, entries)

    # -- checking --
    def call(self, fn, *args, _oserror=False, _exempt=None, **kwargs):
        """Calls fn(*args, **kwargs); records a violation of the property. Returns the result or None."""
        self.calls += 1
        allowed = (ValueError, TypeError, OSError) if _oserror else (ValueError, TypeError)
        start = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # numpy's ComplexWarning when a complex array is cast
                result = fn(*args, **kwargs)
        except allowed as e:
            self.outcomes[f"{getattr(fn, '__name__', '?')}: {type(e).__name__}"] += 1
            result = None
        except Exception as e:  # noqa: BLE001 - the property: nothing else may come out
            self.fail(fn, args, kwargs, f"raised {type(e).__name__}: {str(e)[:200]}")
            result = None
        else:
            self.outcomes[f"{getattr(fn, '__name__', '?')}: returned"] += 1
            bad = non_finite(result)
            if bad and _exempt is not None:
                bad = _exempt(result, bad)
            if bad:
                self.fail(fn, args, kwargs, "returned non-finite numbers: " + "; ".join(bad[:4]))
        seconds = time.perf_counter() - start
        if seconds > CALL_SECONDS:
            self.fail(fn, args, kwargs, f"took {seconds:.1f} s")
        return result

    def fail(self, fn, args, kwargs, what):
        name = getattr(fn, "__qualname__", None) or getattr(fn, "__name__", repr(fn))
        text = ", ".join([describe(a) for a in args] + [f"{k}={describe(v)}" for k, v in kwargs.items()])
        self.failures.append(f"{name}({text}) {what}")

    def done(self):
        print(f"{self.calls} calls:", dict(sorted(self.outcomes.items())))
        assert not self.failures, f"{len(self.failures)} of {self.calls} calls broke the property:\n" + "\n".join(
            self.failures[:20])


@pytest.fixture(autouse=True)
def watchdog(tmp_path, monkeypatch):
    """A hang ends the process with every thread's traceback (a C++ loop holds no Python frame
    that an alarm could interrupt). The working directory is a temporary one: a relative path
    drawn as an output lands there."""
    monkeypatch.chdir(tmp_path)
    faulthandler.dump_traceback_later(HANG_SECONDS, exit=True)
    yield
    faulthandler.cancel_dump_traceback_later()


# --- the module's own part (lgvi_module.cpp) ------------------------------------------------------


def bodies():
    return [lgvi.FreeRigidBody(J), lgvi.FreeRigidBody(np.ones(3)),
            lgvi.FreeRigidBody(rotation([0.3, -0.2, 0.5]) @ np.diag(J) @ rotation([0.3, -0.2, 0.5]).T),
            lgvi.FreeRigidBody(np.array([2.0, 1.0, 2.0 / 3.0]), nonphysical_inertia=True)]


def pendulums():
    return [lgvi.Pendulum3D.paper(), lgvi.Pendulum3D(2.0, J, np.zeros(3), 0.0),
            lgvi.Pendulum3D(1.0, np.array([1.0, 1.0, 0.5]), np.array([0.1, 0.2, 0.3]), 1.62)]


NOT_SYSTEMS = [None, "free-body", 1.0, np.eye(3), lgvi.so3, object()]

CALLS = {"so3": 600, "systems": 600, "step": 300, "simulate": 300, "simulate_baseline": 300,
         "solve_pendulum_transfer": 150, "make_scene": 250, "parse_scene": 250, "load_scene": 150,
         "simulate_scene": 150, "listings": 100, "run_suite": 25, "validate": 25, "solve_ocp": 180}


def admissible(arg, shape):
    """`arg` as the float array the module would accept (the shape, every entry 0 or of
    magnitude in [1e-100, 1e100]), or None."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            m = np.asarray(arg, dtype=float)
        except (TypeError, ValueError, OverflowError):
            return None
    if m.shape != shape or not np.isfinite(m).all():
        return None
    a = np.abs(m)
    return None if ((a != 0) & ((a < 1e-100) | (a > 1e100))).any() else m


def test_so3():
    f = Fuzz("so3")
    for _ in range(CALLS["so3"]):
        f.next()
        which = f.pick(["hat", "exp", "cayley", "vee", "log"])
        fn = getattr(lgvi.so3, which)
        if which == "vee":
            arg = f.rot() if f.chance(0.7) else f.array([[f.rng.uniform(-5, 5) for _ in range(3)] for _ in range(3)])
        elif which == "log":
            arg = f.rot()  # a non-rotation is a ValueError (REPRODUCERS["log-non-rotation"])
        else:
            arg = f.vec3(scale=10.0)
        if f.chance(0.03):
            f.call(fn, arg, arg)  # too many arguments: TypeError
        else:
            f.call(fn, arg)
    f.done()


def test_free_body_and_pendulum():
    f = Fuzz("systems")
    valid_inertias = [J, np.array([1.0, 1.0, 1.0]), np.diag(J), np.array([1e-100, 1.0, 1.0]), np.array([1e100] * 3),
                      np.array([2.0, 1.0, 2.0 / 3.0])]
    systems = bodies() + pendulums()
    for _ in range(CALLS["systems"]):
        f.next()
        what = f.rng.randrange(5)
        if what == 0:
            inertia = f.array(f.pick(valid_inertias))
            if f.chance(0.5):
                f.call(lgvi.FreeRigidBody, inertia)
            else:
                flag = f.pick([True, False, None, 0, 1, 2, -1, 2**64, "x", "", np.bool_(True), 1.5, [], [1], NAN])
                f.call(lgvi.FreeRigidBody, inertia, nonphysical_inertia=flag)
        elif what == 1:
            mass = f.scalar([1.0, 0.5, 1e-100, 1e100, 0.0, True, np.float32(2.0)], huge=True)
            inertia = f.array(f.pick(valid_inertias[:5]))
            rho = f.vec3([0.0, 0.0, 0.3] if f.chance(0.5) else [1e100, -1e100, 1e-100])
            if f.chance(0.8):
                gravity = f.scalar([9.81, 0.0, -9.81, 1e100, 1e-100], huge=True)
                f.call(lgvi.Pendulum3D, mass, inertia, rho, gravity)
            else:
                f.call(lgvi.Pendulum3D, mass, inertia, rho)
        else:
            system = f.pick(systems)
            method = f.pick(["energy", "spatial_momentum"] if isinstance(system, lgvi.FreeRigidBody)
                            else ["energy", "vertical_momentum"])
            Omega = f.vec3(scale=1e3)
            if f.chance(0.05):
                f.call(getattr(system, method), R=f.rot(), Omega=Omega, extra=1.0)
            else:
                f.call(getattr(system, method), f.rot(), Omega)
    f.done()


def test_step():
    """One LGVI step, h |Omega| up to 1e102: outside the rotation update's domain a ValueError
    (REPRODUCERS["step-outside-the-rotation-update"])."""
    f = Fuzz("step")
    systems = bodies() + pendulums()
    small = [NAN, INF, -INF, 0, 0.0, -0.0, 1e-320, 5e-324, 1e308, -1.0, 1e-101, 1e101, 2**1024, np.float32("nan"),
             np.int64(-1), np.float16(6e-8), np.longdouble("1e4000"), None, "", "0.01", b"1", 1 + 2j, [0.01],
             np.zeros(2), object()]
    for _ in range(CALLS["step"]):
        f.next()
        system = f.pick(systems) if f.chance(0.95) else f.pick(NOT_SYSTEMS)
        R = f.rot()
        Omega = f.vec3(scale=f.pick([1.0, 10.0, 1e3]))
        h = f.pick([1e-3, 0.01, 0.05, 1.0, 1e-100, np.float64(0.02), np.array(0.01), np.float32(0.01)]) if f.valid(None) \
            else f.pick(small)
        if f.chance(0.5):
            f.call(lgvi.step, system, R, Omega, h)
        else:
            f.call(lgvi.step, system, R, Omega, h=h, form=f.string(["symmetric", "printed"]))
    f.done()


STEPS = [0, 1, 2, 3, 5, 8, True, False, np.int64(4), np.uint8(3)]


def test_simulate():
    """The LGVI's simulate: a failure is a status with the rows before it (finite)."""
    f = Fuzz("simulate")
    systems = bodies() + pendulums()
    for _ in range(CALLS["simulate"]):
        f.next()
        system = f.pick(systems) if f.chance(0.95) else f.pick(NOT_SYSTEMS)
        kwargs = {}
        if f.chance(0.5):
            kwargs["form"] = f.string(["symmetric", "printed"])
        if f.chance(0.5):
            kwargs["every"] = f.integer([1, 2, 3, 10**12, np.int32(2), True], invalid=[0, 10**12 + 1])
        f.call(lgvi.simulate, system, f.rot(), f.vec3(scale=5.0),
               f.scalar([1e-3, 0.01, 0.1, 1.0, 1e-100, 1e100, True, np.float32(0.5)]),
               f.integer(STEPS, invalid=[10**12 + 1, 10**13, 2**63 - 1]), **kwargs)
    f.done()


def test_simulate_baseline():
    """Every baseline method and coordinate model on tiny horizons (t_final <= 0.05 or invalid).
    An adaptive method's steps grow with |Omega| (up to 1e100 here): a call with a large |Omega|
    passes a small max_steps and ends at it with a status (REPRODUCERS["baseline-step-budget"])."""
    f = Fuzz("simulate_baseline")
    systems = bodies() + pendulums()
    methods = lgvi.baseline_methods()
    models = ["quaternion", "quaternion-renormalized", "euler", "matrix"]
    for _ in range(CALLS["simulate_baseline"]):
        f.next()
        system = f.pick(systems) if f.chance(0.95) else f.pick(NOT_SYSTEMS)
        t_final = f.scalar([1e-3, 0.01, 0.02, 0.05, 1e-100, np.float32(0.01)])
        kwargs = {}
        if f.chance(0.7):
            kwargs["samples"] = f.integer([1, 2, 3, 5, True, np.int64(4)], invalid=[0, 10**7, 10**12, 2**63 - 1])
        if f.chance(0.8):
            kwargs["method"] = f.string(methods)
        if f.chance(0.6):
            kwargs["model"] = f.string(models)
        for key in ("rtol", "atol", "h"):
            if f.chance(0.3):
                valid = [1e-14, 1e-8, 1e-3, 0.1, None] if key != "h" else [1e-3, 5e-3, 1e-2, 2.5e-3, None]
                kwargs[key] = f.scalar(valid, extra=[0.2, 1e-15, 2**63])
        Omega = f.vec3(scale=5.0)
        if f.chance(0.7):
            kwargs["max_steps"] = f.integer([1, 10, 1000, 20_000, np.int64(500)],
                                            invalid=[0, 50_000_001, 10**12, 2**63 - 1])
        else:  # the default budget: a bounded |Omega| keeps the call short
            while (w := admissible(Omega, (3,))) is not None and np.abs(w).max() > 1e3:
                Omega = f.vec3(scale=5.0)
        f.call(lgvi.simulate_baseline, system, f.rot(), Omega, t_final, **kwargs)
    f.done()


def transfer_exempt(result, bad):
    """solve_pendulum_transfer's summary cost and violation are inf when it reports a failure."""
    s = result["summary"]
    if s["converged"]:
        return bad
    return [b for b in bad if not b.startswith(("result['summary']['cost']", "result['summary']['violation']"))]


def test_solve_pendulum_transfer():
    """The indirect pendulum transfer at h >= 0.1 (at most 10 steps), at most 3 iterations."""
    f = Fuzz("solve_pendulum_transfer")
    for _ in range(CALLS["solve_pendulum_transfer"]):
        f.next()
        kwargs = {}
        if f.chance(0.3):
            kwargs["pendulum"] = f.pick(pendulums()) if f.chance(0.8) else f.pick(NOT_SYSTEMS + bodies()[:1])
        kwargs["h"] = f.scalar([1.0, 0.5, 0.25, 0.2, 0.1, True, 0.3, 2.0, np.float32(0.5)])
        if f.chance(0.4):
            kwargs["form"] = f.string(["symmetric", "printed"])
        if f.chance(0.5):
            kwargs["initial_multiplier"] = None if f.chance(0.1) else f.array(
                [f.rng.uniform(-3, 3) for _ in range(6)] if f.chance(0.8) else [1e100] * 6)
        if f.chance(0.5):
            kwargs["tolerance"] = f.scalar([1e-12, 1e-6, 0.1, 1e-300], extra=[0.2])
        kwargs["max_iterations"] = f.integer([1, 2, 3, True], invalid=[0, 10**6 + 1, 2**31])
        f.call(lgvi.solve_pendulum_transfer, _exempt=transfer_exempt, **kwargs)
    f.done()


# --- the harness (harness_bindings.cpp) -----------------------------------------------------------

harness = pytest.mark.skipif(not lgvi.has_harness, reason="the module was built without the harness")

SRC = os.environ.get("LGVI_SOURCE_DIR") or os.path.join(os.path.dirname(__file__), "..", "..")
SCENES = os.path.join(SRC, "experiments", "scenes")
SYSTEMS = ["free-body", "pendulum", "dumbbell", "cart-pendulum", "connected-bodies"]
# The tables of a scene of each system (from the shipped scenes), as make_scene takes them.
TABLES = {
    "free-body": ({"inertia": [0.13, 0.28, 0.17]}, {"R": np.eye(3), "Omega": [0.05, 0.05, 3.0]}),
    "pendulum": ({"mass": 1.0, "inertia": [0.13, 0.28, 0.17], "rho": [0.0, 0.0, 0.3], "gravity": 9.81},
                 {"R": np.eye(3), "Omega": [4.14, 4.14, 4.14]}),
    "dumbbell": ({"mass": 1.0, "mu": 1.0, "rho": [0.15, 0.0, 0.0], "sphere_radius": 0.05},
                 {"x": [1.0, 0.0, 0.0], "R": [[0, -1, 0], [1, 0, 0], [0, 0, 1]], "v": [0.0, 0.98, 0.0],
                  "Omega": [0.0, 0.0, 0.98]}),
    "cart-pendulum": ({"cart_mass": 1.0, "mass": 1.0, "inertia": [1.03, 1.04, 0.03], "d": [0.0, 0.0, 1.0],
                       "gravity": 9.81},
                      {"R": rotation([0.6, 0, 0]), "Omega": [0.5, 1.0, 2.0], "q": [0.0, 0.0], "q_dot": [0.0, 0.0]}),
    "connected-bodies": ({"mass1": 1.5, "inertia1": [[0.18, 0.32, 0.32], [0.32, 1.88, -0.06], [0.32, -0.06, 1.86]],
                          "d1": [-1.08, 0.2, 0.2], "mass2": 1.0,
                          "inertia2": [[0.11, -0.18, -0.18], [-0.18, 0.89, -0.04], [-0.18, -0.04, 0.88]],
                          "d2": [0.9, 0.2, 0.2]},
                         {"Omega1": [0.5, -0.4, 0.3], "Omega2": [-0.2, 0.6, 0.1]}),
}
CONTROL = {"amplitude": [0.5, 0.3, 0.4], "frequency": [0.5, 0.9, 1.3], "phase": [0.0, 0.5, 1.0]}

# Values of a make_scene table: anything make_scene writes as TOML, or refuses with ValueError.
TOML_VALUES = [NAN, INF, -INF, 0.0, -0.0, 1e-320, 1e308, -1.0, 1e-100, 1e100, 1e101, 2**63 - 1, -(2**63), 0, True,
               2**63, 2**64, -(2**63) - 1, np.uint64(2**64 - 1), "\ud800", ["\udcff"], {"\ud800": 1},
               False, None, "", "\0", "é", "x" * 10_000, "[1, 2]", '"', "\\", b"bytes", 1 + 1j, (0.1, 0.2, 0.3),
               {0.1, 0.2}, object(), range(3), np.float32(0.5), np.int8(-1), np.uint64(7), np.bool_(True),
               np.longdouble("1e4000"), np.array([0.1, 0.2, 0.3], dtype=np.float32), np.array([1, 2, 3]),
               np.array([1, None, 3], dtype=object), np.array([1j, 0, 0]), np.array(0.5), np.zeros((0,)),
               np.eye(3).T, np.zeros((2, 2, 2)), [], [[]], [0.1, "x", 3], [[0.1, 0.2], [0.3]], {}, {"a": 1},
               {1: 2.0}, {None: 1}, {(1, 2): [3]}, {"": ""}, {"\0": 1}]


def nested(depth, leaf):
    for _ in range(depth):
        leaf = [leaf]
    return leaf


def spoil_table(f, table):
    """A table (dict) with one or two keys spoiled, added, removed, or the table replaced."""
    if f.chance(0.1):
        return f.pick([None, [], "x", 5, (("inertia", 1),), np.eye(3)])
    t = dict(table)
    for _ in range(1 + f.rng.randrange(2)):
        r = f.rng.random()
        keys = list(t)
        if r < 0.45 and keys:
            k = f.pick(keys)
            v = t[k]
            numeric = None
            if isinstance(v, (list, np.ndarray)):
                try:
                    numeric = np.asarray(v, dtype=float)
                except (TypeError, ValueError):
                    pass
            if numeric is not None and numeric.ndim in (1, 2) and numeric.size > 0 and f.chance(0.5):
                t[k] = f.array(numeric)
            else:
                t[k] = f.pick(TOML_VALUES)
        elif r < 0.65:
            t[f.pick(["unknown", "mass", "Omega", "R", 1, None, 2.5, (1,), "", "é", "\0", "a" * 300, "a.b", "[x]",
                      '"', "quaternion", "euler", "omega_space", "nonphysical_inertia", "orbit_rate"])] = \
                f.pick(TOML_VALUES)
        elif r < 0.8 and keys:
            del t[f.pick(keys)]
        elif r < 0.9:
            t[f.pick(keys) if keys else "x"] = nested(f.pick([1, 4, 31, 32, 33, 40, 20_000]), f.pick([0.5, "x", {}]))
        else:
            t[f.pick(keys) if keys else "x"] = f.pick(TOML_VALUES)
    return t


def scene_exempt(result, bad):
    """The summary statistics without a value (NaN, the CLI's null): a run of <= 2 rows has no
    energy trend error, a zero initial energy no relative energy error."""
    s = result.get("summary", {})
    keep = []
    for b in bad:
        if b.startswith("result['summary']['energy_drift_rate_stderr']") and s.get("output_rows", 0) <= 2:
            continue
        if b.startswith("result['summary']['max_energy_error_relative']") and s.get("energy0") == 0.0:
            continue
        keep.append(b)
    return keep


def method_for(f, scene, methods):
    m = f.pick(methods)
    model = f.pick(m["models"]) if m["models"] else None
    return m["name"], model


def run_scene(f, scene, methods, p=1.0):
    """lgvi.simulate of a scene that came back, when it is short (steps <= 60), whatever its
    name (REPRODUCERS["simulate-scene-name"])."""
    if not isinstance(scene, lgvi.Scene) or scene.steps > 60 or not f.chance(p):
        return
    name, model = method_for(f, scene, methods)
    f.call(lgvi.simulate, scene, name, model, _exempt=scene_exempt)


@pytest.fixture(scope="module")
def methods():
    return lgvi.methods() if lgvi.has_harness else []


@pytest.fixture(scope="module")
def paths(tmp_path_factory):
    """Hostile and valid paths: a tiny scenes directory (one 10-step pendulum), files of every
    kind of bad content, a directory, a FIFO, special files, missing and over-long names."""
    d = tmp_path_factory.mktemp("fuzz")
    scenes = d / "scenes"
    scenes.mkdir()
    with open(os.path.join(SCENES, "pendulum.toml")) as fh:
        pendulum = fh.read()
    (scenes / "tiny.toml").write_text(pendulum.replace("t_final = 20.0", "t_final = 0.01"))
    (d / "empty.toml").write_text("")
    (d / "binary.toml").write_bytes(bytes(range(256)) * 4)
    (d / "nul.toml").write_bytes(pendulum.encode().replace(b"gravity", b"grav\0ity"))
    (d / "latin1.toml").write_bytes(pendulum.replace("3D", "3D \xe9").encode("latin-1"))
    (d / "cut.toml").write_text(pendulum[: len(pendulum) // 2])
    (d / "big.toml").write_text("# " + "x" * 2_000_000 + "\n" + pendulum)
    (d / "é.toml").write_text(pendulum.replace("t_final = 20.0", "t_final = 0.01"))
    unreadable = d / "unreadable.toml"
    unreadable.write_text(pendulum)
    unreadable.chmod(0)
    fifo = d / "fifo.toml"
    if hasattr(os, "mkfifo"):
        os.mkfifo(fifo)
    files = [str(scenes / "tiny.toml"), d / "empty.toml", d / "binary.toml", d / "nul.toml", d / "latin1.toml",
             d / "cut.toml", d / "big.toml", d / "é.toml", unreadable, fifo, d, d / "missing.toml",
             d / ("x" * 300 + ".toml"), "/dev/null", "/proc/self/status", str(d / "é.toml").encode()]
    out = [d / "out", d / "out" / "é", d / "missing" / "deep" / "out", d / "empty.toml", d / ("y" * 300), "", fifo,
           "/proc/out", str(d / "out2").encode()]
    return {"dir": d, "scenes": scenes, "files": files, "out": out, "pendulum": pendulum}


@harness
def test_make_scene(methods):
    f = Fuzz("make_scene")
    for _ in range(CALLS["make_scene"]):
        f.next()
        system = f.string(SYSTEMS)
        params, initial = TABLES[system if system in SYSTEMS else "free-body"]
        params = spoil_table(f, params) if f.chance(f.rate) else dict(params)
        initial = spoil_table(f, initial) if f.chance(f.rate) else dict(initial)
        kwargs = {"h": f.scalar([0.01, 5e-3, 1e-3, 1e-100, np.float32(0.01)], huge=True),
                  "t_final": f.scalar([0.01, 0.02, 0.05, 1e100], huge=True)}
        if f.chance(0.3):
            kwargs["form"] = f.string(["symmetric", "printed"])
        if f.chance(0.3):
            kwargs["output_every"] = f.integer([1, 2, 3, 10**12, 2**63 - 1, True], invalid=[0, 10**12 + 1])
        if f.chance(0.2):
            kwargs["control"] = None if f.chance(0.2) else spoil_table(f, CONTROL)
        if f.chance(0.3):
            kwargs["name"] = f.pick(["scene", "x", "", "é", "../up", "a/b", "a" * 300, "\0", "\ud800", ".", "-", None,
                                     5, b"bytes"])
        if f.chance(0.2):
            kwargs["description"] = f.pick([None, "", "x\0y", "\ud800", "d" * 100_000, "é\n\t\"'\\", 5, b"x"])
        args = (system, params, initial) if f.chance(0.9) else (system, params)
        scene = f.call(lgvi.make_scene, *args, **kwargs)
        run_scene(f, scene, methods, p=0.5)
    f.done()


def mutate_toml(f, text):
    """One to three edits of a scene file's text: a value replaced, a line dropped, repeated or
    cut, bytes inserted, a deep nesting, a long string."""
    lines = text.split("\n")
    for _ in range(1 + f.rng.randrange(3)):
        r = f.rng.random()
        i = f.rng.randrange(len(lines))
        if r < 0.4 and "=" in lines[i]:
            key = lines[i].split("=", 1)[0]
            lines[i] = key + "= " + f.pick([
                "nan", "+nan", "-nan", "inf", "-inf", "1e999", "-0.0", "1e-320", "5e-324", "1e308", "1e101", "1e-101",
                "0", "-1", "9223372036854775807", "9223372036854775808", "-9223372036854775809", "0x7fffffffffffffff",
                "0o777", "0b101", "1_000", "1__0", "01", ".5", "5.", "1e", "true", '"3"', "''", '"\\u0000"', '"é"',
                '"\\ud800"', "[]", "{}", "[[1, 2], [3]]", "[1, [2, [3, [4]]]]", "1979-05-27T07:32:00Z", "07:32:00",
                "[" * 40 + "]" * 40, '"' + "x" * 100_000 + '"', "[1.0, 2.0, nan]", "[1e308, 1e308, 1e308]",
                "[0.0, 0.0, 0.0]", "[1e-320, 1, 1]", "[[1, 0, 0], [0, 1, 0], [0, 0, -1]]", "{ x = 1 }", "",
            ])
        elif r < 0.55:
            del lines[i]
        elif r < 0.65:
            lines.insert(i, lines[i])
        elif r < 0.75:
            lines[i] = lines[i][: f.rng.randrange(len(lines[i]) + 1)]
        elif r < 0.9:
            j = f.rng.randrange(len(lines[i]) + 1)
            lines[i] = lines[i][:j] + f.pick(["\0", "\x7f", "é", "\ud7ff", "\t", "\r", "[", "]", "=", '"', "#", "\\",
                                              "\ufeff", "\u2028", "💥", "[integration]", "\n[parameters]\n"]) + lines[i][j:]
        else:
            lines.insert(i, f.pick(["[" * 1000, "a = " + "[" * 1000 + "]" * 1000, "a.b.c.d.e.f.g.h = 1",
                                    "[[parameters]]", "[initial.R]", "x = " + "{a = " * 100 + "1" + "}" * 100]))
    return "\n".join(lines)


@harness
def test_parse_scene(methods):
    f = Fuzz("parse_scene")
    texts = {}
    for name in lgvi.scene_names():
        with open(os.path.join(SCENES, name + ".toml"), encoding="utf-8") as fh:
            texts[name] = fh.read()
    for _ in range(CALLS["parse_scene"]):
        f.next()
        text = texts[f.pick(sorted(texts))]
        r = f.rng.random()
        if r < 0.65:
            text = mutate_toml(f, text)
        elif r < 0.7:
            text = f.pick(HOSTILE_STRINGS + [text.encode(), text.encode("utf-16"), text[: len(text) // 3]])
        kwargs = {}
        if f.chance(0.7):
            kwargs["t_final"] = f.scalar([0.01, 0.02, 0.005, None], huge=True)
        if f.chance(0.3):
            kwargs["h"] = f.scalar([1e-3, 5e-3, 0.01, None], huge=True)
        if f.chance(0.2):
            kwargs["form"] = f.string(["symmetric", "printed", None])
        if f.chance(0.2):
            kwargs["output_every"] = f.integer([None, 1, 2, 10**12, 2**63 - 1], invalid=[0, 10**12 + 1])
        if f.chance(0.2):
            kwargs["name"] = f.pick(["x", "", "é", "../up", "a/b", "a" * 300, "\0", "\ud800", None, 5])
        scene = f.call(lgvi.parse_scene, text, **kwargs)
        run_scene(f, scene, methods, p=0.7)
    f.done()


@harness
def test_load_scene(paths, methods):
    f = Fuzz("load_scene")
    names = lgvi.scene_names()
    dirs = [None, paths["scenes"], SCENES, paths["dir"], "", "/nonexistent", paths["files"][1], "\0", "\udcff", 5,
            b"/nonexistent", "d" * 5000, "/proc/self"]
    for _ in range(CALLS["load_scene"]):
        f.next()
        r = f.rng.random()
        if r < 0.4:
            scene, scenes_dir = f.pick(names), None
        elif r < 0.55:
            scene, scenes_dir = "tiny", f.pick(dirs)
        elif r < 0.8:
            scene, scenes_dir = f.pick(paths["files"]), None
        else:
            scene, scenes_dir = f.string(names), f.pick(dirs)
        if isinstance(scene, os.PathLike):
            scene = str(scene)
        kwargs = {}
        if scenes_dir is not None or f.chance(0.1):
            kwargs["scenes_dir"] = scenes_dir
        if f.chance(0.8):
            kwargs["t_final"] = f.scalar([0.01, 0.05, 0.1, None], huge=True)
        if f.chance(0.3):
            kwargs["h"] = f.scalar([1e-3, 5e-3, 0.01, None], huge=True)
        if f.chance(0.2):
            kwargs["form"] = f.string(["symmetric", "printed", None])
        if f.chance(0.2):
            kwargs["output_every"] = f.integer([None, 1, 2, 10**12], invalid=[0, 10**12 + 1, 2**63 - 1])
        loaded = f.call(lgvi.load_scene, scene, **kwargs)
        run_scene(f, loaded, methods, p=0.4)
    f.done()


@harness
def test_simulate_scene(paths, methods):
    """lgvi.simulate of short scenes with every method, model, tolerance and csv path."""
    f = Fuzz("simulate_scene")
    scenes = [lgvi.load_scene(n, t_final=3 * lgvi.load_scene(n).h) for n in lgvi.scene_names()]
    names = [m["name"] for m in methods]
    models = ["quaternion", "quaternion-renormalized", "euler", "matrix"]
    for i in range(CALLS["simulate_scene"]):
        f.next()
        scene = f.pick(scenes) if f.chance(0.95) else f.pick([None, "free-body", lgvi.FreeRigidBody(J), 5])
        m = f.pick(methods)
        kwargs = {"method": m["name"] if f.chance(0.6) else f.string(names)}
        if m["models"] and f.chance(0.8):
            kwargs["model"] = f.pick(m["models"])
        elif f.chance(0.4):
            kwargs["model"] = f.string(models + [None])
        for key in ("rtol", "atol"):
            if f.chance(0.25):
                kwargs[key] = f.scalar([1e-14, 1e-8, 1e-3, 0.1, None], huge=True, extra=[0.2, 1e-15])
        oserror = False
        if f.chance(0.25):
            kwargs["csv"] = f.pick([paths["dir"] / f"run{i}.csv", paths["dir"] / "é" / "x.csv", paths["dir"],
                                    paths["dir"] / ("z" * 300), "", "-", "\0", None, 5, paths["dir"] / "missing" / "x.csv",
                                    str(paths["dir"] / f"b{i}.csv").encode(), "/proc/self/x.csv"])
            oserror = kwargs["csv"] is not None
        f.call(lgvi.simulate, scene, _oserror=oserror, _exempt=scene_exempt, **kwargs)
    f.done()


@harness
def test_listings(paths):
    """scene_names, suite_cases (only listed: never run), and the argument-less listings."""
    f = Fuzz("listings")
    suites = [name for name, _ in lgvi.suites()]
    dirs = [None, paths["scenes"], paths["dir"], "", "/nonexistent", paths["files"][1], "\0", "\udcff", 5,
            b"/nonexistent", "d" * 5000, paths["files"][9]]
    for _ in range(CALLS["listings"]):
        f.next()
        r = f.rng.random()
        if r < 0.3:
            f.call(lgvi.scene_names, f.pick(dirs))
        elif r < 0.8:
            kwargs = {}
            if f.chance(0.5):
                kwargs["quick"] = f.pick([True, False, None, 0, 1, "x", np.bool_(False), 1.5, []])
            if f.chance(0.5):
                kwargs["scenes_dir"] = f.pick(dirs)
            f.call(lgvi.suite_cases, f.string(suites), **kwargs)
        else:
            fn = f.pick([lgvi.methods, lgvi.suites, lgvi.metric_groups, lgvi.baseline_methods])
            if f.chance(0.5):
                f.call(fn)
            else:
                f.call(fn, f.pick([None, 1, "x"]))  # no argument: TypeError
    f.done()


@harness
def test_run_suite(paths):
    """run_suite: the default suite over the tiny scenes directory (2 cases of 10 steps), or
    invalid arguments; never another suite (the others run for seconds to hours); plots on in
    some (REPRODUCERS["run-suite-plots-all-zero"])."""
    f = Fuzz("run_suite")
    for i in range(CALLS["run_suite"]):
        f.next()
        name = "default" if f.chance(0.6) else f.pick(HOSTILE_STRINGS[:20] + ["nope", "Default", "default\0"])
        out = paths["dir"] / f"suite{i}" if f.chance(0.6) else f.pick(paths["out"] + [None, 5, "\0"])
        kwargs = {"scenes_dir": paths["scenes"] if f.chance(0.8) else f.pick(["/nonexistent", "", None, 5, "\0"])}
        if kwargs["scenes_dir"] is None:  # the shipped scenes: a real run; keep it a listing error
            name = "nope"
        if f.chance(0.3):
            kwargs["quick"] = f.pick([True, False, None, 1, "x"])
        if f.chance(0.3):
            kwargs["jobs"] = f.pick([1, 2, 0, -1, 2**32, 2**64, None, 1.5, "2", True, 10**9])
        if f.chance(0.3):
            kwargs["shard"] = f.pick(["0/1", "0/2", "1/2", "2/2", "1/0", "", "\0", "a/b", "0/99999999999999999999",
                                      "0 / 2", "-1/2", None, 5, "0/2/3"])
        if f.chance(0.3):
            kwargs["plots"] = f.pick([True, False, 1, 0, None, 0.0, "x", []])
        if f.chance(0.2):
            kwargs["progress"] = f.pick([False, 0, None, "x", []])
        f.call(lgvi.run_suite, name, out, _oserror=True, **kwargs)
    f.done()


@harness
def test_validate(paths):
    """validate with at least one unknown group in `only` (refused before any metric is
    computed: the gate itself runs for minutes), and hostile accepted files."""
    f = Fuzz("validate")
    groups = [name for name, _ in lgvi.metric_groups()]
    for _ in range(CALLS["validate"]):
        f.next()
        only = [f.string(groups, p_valid=0.5) for _ in range(f.rng.randrange(3))]
        only.insert(f.rng.randrange(len(only) + 1), f.pick(["nonsense", "", "\0", "é", "EXACT", "exact ", "a" * 10000]))
        kwargs = {"only": only if f.chance(0.9) else f.pick(["exact", None, 5, [None], ("nonsense",)])}
        if f.chance(0.5):
            kwargs["quick"] = f.pick([True, False, None, 0, "x"])
        if f.chance(0.6):
            kwargs["accepted"] = f.pick(paths["files"] + [None, 5, "\0"])
        if f.chance(0.3):
            kwargs["scenes_dir"] = f.pick([paths["scenes"], "/nonexistent", None, 5])
        f.call(lgvi.validate, **kwargs)
    f.done()


# solve_ocp's options by family: (valid, outside the option's range); test_solve_ocp also draws
# values of another type (WRONG_TYPES, REPRODUCERS["solve-ocp-cast"]).
WRONG_TYPES = [None, "x", "\ud800", b"x", 1.5, 2**64, -(2**64), 2**1024, [None], ["x"] * 6, {}, object(), 1 + 1j]
OCP_COMMON = {
    "form": (["symmetric", "printed"], ["", "\0", "é", "SYMMETRIC", "a" * 10_000]),
    "tolerance": ([1e-10, 1e-6, 0.1, 1e-300], [0.2, 0.0, -1.0, NAN, INF, 1e-320, 1e308, 2**63 - 1]),
    "t_final": ([1.0, 0.5, 2.0, 1e100], [0.0, -0.0, -1.0, NAN, INF, 1e-320, 1e101, 2**1023 * 2.0]),
}
OCP_INDIRECT = {
    "decomposition": ([True, False, 0, 1, np.bool_(True)], []),
    "merit": (["velocity", "momentum"], ["", "nope", "\0", "velocity\0"]),
    "globalization": (["newton-armijo", "levenberg-marquardt", "homotopy", "continuation"], ["", "nope", "é"]),
    "lm_damping": ([1e-3, 1.0, 1e10], [1e11, 0.0, -1.0, NAN, INF, 1e-320]),
    "nonmonotone_memory": ([1, 5, 1000], [1001, 0, -1, 2**63 - 1, -(2**63)]),
    "guess": ([[1.0] * 6, [0.5] * 6, [0.0] * 6, [1e100] * 6, [1e-100] * 6, np.ones(6), np.ones(6, dtype=np.float32),
               (1.0,) * 6, [1.0] * 12, [0.1] * 12],
              [[NAN] * 6, [INF] * 6, [1e-320] * 6, [1e101] * 6, [1.0] * 5, [1.0] * 7, [], [1.0] * 13]),
    "sphere_radius": ([0.05, 0.1, 1.0, 1e-100, 1e100], [0.0, -1.0, NAN, INF, 1e-320, 1e101]),
}
OCP_DIRECT = {
    "knots": ([3, 4, 5], [2, 0, -1, 1001, 10**12, 2**63 - 1]),
    "spline": (["not-a-knot", "natural"], ["clamped", "", "nope"]),
    "gradients": (["exact", "finite-difference"], ["forward", "", "nope"]),
    "starts": ([1, 2], [0, -1, 10**4 + 1, 2**63 - 1]),
    "seed": ([0, 1, 2**31 - 1], [2**31, -1, 2**63 - 1]),
    "first_start": ([0, 1, 5], [-1, 10**6 + 1, 2**63 - 1]),
    "solver": (["slsqp", "ipopt"], ["", "nope", "\0", "IPOPT"]),
    "hessian": (["exact", "limited-memory", "cost"], ["", "nope"]),
    "state_guess": (["simulated", "geodesic"], ["", "nope"]),
    "shooting_interval": ([2, 5, 10], [0, -1, 10**6 + 1, 2**63 - 1]),
}


@harness
def test_solve_ocp(paths):
    """solve_ocp on every system and [ocp] scene, with at most 12 steps (or h >= 0.1) and at
    most 3 iterations (or an invalid count), options of both families mixed in."""
    f = Fuzz("solve_ocp")
    indirect = ["pendulum", "dumbbell", "ocp-pendulum", "ocp-dumbbell", "ocp-free-body-slew"]
    direct = ["cart-pendulum", "connected-bodies", "ocp-cart-pendulum", "ocp-connected-bodies"]
    ocp_copy = paths["dir"] / "my-ocp.toml"
    with open(os.path.join(SCENES, "ocp-pendulum.toml")) as fh:
        ocp_copy.write_text(fh.read())
    hostile = [str(paths["scenes"] / "tiny.toml")] + [str(p) for p in paths["files"][1:13]] + \
        ["", "\0", "é", "bicycle", "free-body", "a" * 5000, "../pendulum"]

    def exempt(result, bad):
        """A run that did not converge states why in its summary and history (a singular
        sensitivity's condition number is inf); its trajectory must still be finite."""
        if result.get("converged"):
            return bad
        return [b for b in bad if not b.startswith(("result['summary']", "result['history']"))]

    def option(table, key):
        good, bad = table[key]
        if f.chance(f.rate * 0.2):
            return f.pick(WRONG_TYPES)
        return f.pick(good) if not bad or f.valid(None) else f.pick(bad)

    for i in range(CALLS["solve_ocp"]):
        f.next()
        system = f.pick(indirect + direct + [str(ocp_copy)]) if f.valid(None) else f.pick(hostile)
        family = OCP_DIRECT if system in direct or (system not in indirect and f.chance(0.3)) else OCP_INDIRECT
        kwargs = {}
        if f.chance(0.15):
            kwargs["h"] = option({"h": ([0.1, 0.25, 0.5], [0.0, -1.0, NAN, INF, 1e-320, 1e-100, 1e101, 0.3])}, "h")
        else:
            valid_steps = [6, 8, 10, 12] if family is OCP_DIRECT else [2, 4, 6, 10, 12, True]
            kwargs["steps"] = option({"steps": (valid_steps, [0, -1, 10**6 + 1, 2**63 - 1, -(2**63)])}, "steps")
        kwargs["max_iterations"] = option({"m": ([1, 2, 3], [0, -1, 10**8 + 1, 2**63 - 1])}, "m")
        options = dict(OCP_COMMON, **family)
        for key in f.rng.sample(sorted(options), f.rng.randrange(4)):
            kwargs[key] = option(options, key)
        if {"shooting_interval", "hessian", "state_guess"} & set(kwargs):
            kwargs.setdefault("solver", "ipopt")
        if {"first_start", "starts", "seed"} & set(kwargs):
            kwargs.setdefault("solver", "slsqp")
        if f.chance(f.rate * 0.3):  # an option of the other family, or of none
            other = OCP_INDIRECT if family is OCP_DIRECT else OCP_DIRECT
            key = f.pick(sorted(other) + ["stepz", "out_dir", "", "\0"])
            kwargs[key] = option(other, key) if key in other else 1
        oserror = False
        if f.chance(0.15):
            kwargs["out"] = f.pick([paths["dir"] / f"ocp{i}", paths["dir"] / "é" / f"ocp{i}"] + paths["out"] +
                                   [None, "\ud800", 1.5, [None]])
            oserror = True
        f.call(lgvi.solve_ocp, system, _oserror=oserror, _exempt=exempt, **kwargs)
    f.done()


# --- the defects this fuzz found, each with its reproducer and the fixed behaviour ----------------


def self_holding_list():
    x = [1.0]
    x.append(x)
    return x


def free_body_scene(**kwargs):
    return lgvi.make_scene("free-body", {"inertia": [1.0, 2.0, 2.5]}, {"Omega": [0.0, 0.0, 1.0]}, h=0.01,
                           t_final=0.02, **kwargs)


def budget_reached(result):
    s = result["stats"]
    assert s["status"] != "completed" and "step budget of 1000 steps" in s["failure_detail"], s
    assert result["t"][-1] < 1.0 and not non_finite(result)


def rows_returned(result):
    assert len(result["t"]) == 3 and not non_finite(result, "result")


def stopped_with_finite_rows(result):
    assert not result["converged"] and result["summary"]["status"] == "sweep failed", result["summary"]["status"]
    assert "is not finite after step" in result["summary"]["status_detail"], result["summary"]["status_detail"]
    assert not non_finite(result["trajectory"], "trajectory")


def tiny_suite_with_plots():
    """The default suite with its figures over one 10-step pendulum, whose vertical momentum
    error is exactly 0 at every sample."""
    import tempfile
    with open(os.path.join(SCENES, "pendulum.toml")) as fh:
        pendulum = fh.read()
    with tempfile.TemporaryDirectory() as d:
        scenes = os.path.join(d, "scenes")
        os.mkdir(scenes)
        with open(os.path.join(scenes, "tiny.toml"), "w") as fh:
            fh.write(pendulum.replace("t_final = 20.0", "t_final = 0.01"))
        rows = lgvi.run_suite("default", os.path.join(d, "out"), scenes_dir=scenes, plots=True)
        figures = sorted(f for f in os.listdir(os.path.join(d, "out")) if f.endswith(".png"))
    assert len(rows) == 2 and figures == ["tiny-energy.png", "tiny-momentum.png", "tiny-orthogonality.png"], figures
    return rows


# name: (the call, what it must do: an exception type and a part of its message, or a check of its
# result). Before the fix each raised RuntimeError, crashed, returned NaN or ran for minutes.
REPRODUCERS = {
    # RuntimeError 'the rotation update failed'.
    "step-outside-the-rotation-update": (
        lambda: lgvi.step(lgvi.FreeRigidBody(J), np.eye(3), np.array([10.0, 0, 0]), 1.0),
        (ValueError, "h: the rotation update failed")),
    # array([nan, nan, nan]): the precondition was not checked.
    "log-non-rotation": (lambda: lgvi.so3.log(-np.ones((3, 3))), (ValueError, "R: not a rotation matrix")),
    # Minutes: up to the solvers' 5e7-step budget.
    "baseline-step-budget": (
        lambda: lgvi.simulate_baseline(lgvi.FreeRigidBody(J), np.eye(3), np.array([1e10, 0, 0]), 1.0, samples=4,
                                       max_steps=1000),
        budget_reached),
    "baseline-step-budget-range": (
        lambda: lgvi.simulate_baseline(lgvi.FreeRigidBody(J), np.eye(3), np.ones(3), 1.0, max_steps=0),
        (ValueError, "max_steps")),
}

HARNESS_REPRODUCERS = {
    # RuntimeError 'Unable to cast Python instance to C++ type' (every int cast to int64).
    "make-scene-int64": (lambda: lgvi.make_scene("free-body", {"inertia": [2**64, 1, 1]}, {}, h=0.1, t_final=1.0),
                         (ValueError, "parameters.inertia: an integer outside")),
    "make-scene-uint64": (lambda: lgvi.make_scene("free-body", {"inertia": np.array([2**64 - 1, 1, 1], dtype=np.uint64)},
                                                  {}, h=0.1, t_final=1.0), (ValueError, "64-bit")),
    # RuntimeError: a lone surrogate cannot be encoded.
    "make-scene-surrogate": (lambda: lgvi.make_scene("free-body", {"inertia": "\ud800"}, {}, h=0.1, t_final=1.0),
                             (ValueError, "parameters.inertia: not valid Unicode")),
    "make-scene-surrogate-key": (lambda: lgvi.make_scene("free-body", {"\ud800": 1}, {}, h=0.1, t_final=1.0),
                                 (ValueError, "not valid Unicode")),
    # A segmentation fault: one C++ frame per level.
    "make-scene-nesting": (lambda: lgvi.make_scene("free-body", {"inertia": nested(20_000, 1.0)}, {}, h=0.1,
                                                   t_final=1.0), (ValueError, "nested more than 32 levels")),
    "make-scene-self-holding-list": (lambda: lgvi.make_scene("free-body", {"inertia": self_holding_list()}, {}, h=0.1,
                                                             t_final=1.0), (ValueError, "nested more than")),
    # RuntimeError 'Unable to cast Python instance to C++ type'.
    "solve-ocp-cast": (lambda: lgvi.solve_ocp("pendulum", h="x"), (TypeError, "h: expected float, got str")),
    "solve-ocp-cast-int": (lambda: lgvi.solve_ocp("pendulum", steps=2**64), (ValueError, "steps: an integer")),
    "solve-ocp-cast-list": (lambda: lgvi.solve_ocp("pendulum", guess=[None] * 6), (TypeError, "guess: expected")),
    "solve-ocp-cast-out": (lambda: lgvi.solve_ocp("pendulum", out=5), (TypeError, "out: expected a path")),
    # A trajectory row of NaN momenta (the smallest principal moment ~1e-200, in the documented
    # range): a sweep that overflows now stops before it.
    "dumbbell-sphere-radius": (lambda: lgvi.solve_ocp("dumbbell", steps=6, max_iterations=3, sphere_radius=1e-100),
                               stopped_with_finite_rows),
    # Infinite multipliers in the trajectory.
    "pendulum-huge-horizon": (lambda: lgvi.solve_ocp("pendulum", steps=6, max_iterations=3, t_final=1e100,
                                                     guess=[1e100] * 6), stopped_with_finite_rows),
    # OSError 'gnuplot momentum.gp failed: all points y value undefined'.
    "run-suite-plots-all-zero": (tiny_suite_with_plots, lambda rows: None),
    # OSError 'File name too long' / a NUL: the temporary CSV was named after the scene.
    "simulate-scene-name": (lambda: lgvi.simulate(free_body_scene(name="a" * 300)), rows_returned),
    "simulate-scene-name-nul": (lambda: lgvi.simulate(free_body_scene(name="\0")), rows_returned),
}


def check_reproducer(call, expected):
    if callable(expected):
        expected(call())
        return
    kind, part = expected
    with pytest.raises(kind) as e:
        call()
    assert part in str(e.value), str(e.value)


@pytest.mark.parametrize("name", sorted(REPRODUCERS))
def test_reproducers(name):
    check_reproducer(*REPRODUCERS[name])


@harness
@pytest.mark.parametrize("name", sorted(HARNESS_REPRODUCERS))
def test_harness_reproducers(name):
    check_reproducer(*HARNESS_REPRODUCERS[name])
