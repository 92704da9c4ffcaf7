"""The core's argument checks and size limits: the one rule for each kind of argument.

Every other layer's ``checks.py`` calls these rules and passes its own sentence (``message=``),
so an error line keeps its wording while the rule stays in one place.

One rule for integer arguments (``as_int``, ``check_int``, ``check_count``): Python and numpy
integers are accepted, bools and floats (even ``3.0``) are not. One rule for real numbers
(``check_real``): finite Python or numpy reals, not bools; a huge integer such as ``10**400`` is
refused by name instead of raising ``OverflowError``. One rule for enums (``check_choice``) and one
for seeds (``check_seed``). ``message`` is a format string with ``{name}``, ``{value}`` (its repr),
``{shown}`` (a short repr), ``{lo}``, ``{hi}`` and ``{choices}``.

The limits below are checked before anything large is allocated; README "Limits" states them.

=======================  ==================================================================
``as_int``               THE integer rule: a Python int, or None (bools, floats, strings)
``check_int``            integers (Python, numpy) in bounds; bools, floats, strings refused
``check_count``          a size or count (``n_robots``, ``max_steps``): an integer >= 1
``check_real``           finite reals; bools, complex, strings, ``10**400`` refused
``check_choice``         one of a fixed set of values (collisions, render modes, encodings)
``check_seed``           None or a non-negative integer
``check_action``         an action, an integer in 0..4 (``ACTION_HELP`` names them)
``unexpected_keyword``   Python's own ``TypeError`` for an unknown keyword, then the known ones
``real_array``           a float64 array of real numbers; complex, strings, bools refused
``check_level_size``     ``width * height <= MAX_LEVEL_CELLS``
``check_dense_states``   the dense model ``P[s, a, s']`` within ``MAX_DENSE_STATES``
``check_batch``          a batch engine (vector env) within ``MAX_BATCH_ENVS``, ``MAX_BATCH_ROBOTS``, ``MAX_BATCH_OBS``
``check_global_view``    one race's "global" observations within ``MAX_BATCH_OBS``
``check_view_radius``    "local"'s ``view_radius``: at most the radius that sees the whole level
``check_nearest_k``      "nearest"'s ``k``: at most ``MAX_NEAREST_K``
``check_view_numbers``   one race's "local" or "nearest" observations within ``MAX_BATCH_OBS``
``shown``                a short ``repr`` for error messages (never a huge input in full)
=======================  ==================================================================
"""

from __future__ import annotations

import math
import numbers
import operator
from collections.abc import Collection, Sequence
from typing import Any

import numpy as np

from .actions import N_ACTIONS, Action

MAX_LEVEL_CELLS = 65_536  # width * height: a 256x256 maze, or a one-row corridor 65,536 cells long
MAX_LEVEL_TEXT_CHARS = 2 * 1024 * 1024  # a level text (or file, in bytes): the largest level takes under 700 kB, CRLF included
MAX_DENSE_STATES = 2_500  # planning's dense P[s, a, s']: 5 * S * S floats, 250 MB at 2,500 states (50x50)
MAX_BATCH_ENVS = 65_536  # envs of one batch engine / vector env: each has its own generator (~1 kB, ~60 us to make)
MAX_BATCH_ROBOTS = 1 << 20  # n_envs * n_robots: about 100 bytes of arrays per robot and step
MAX_BATCH_OBS = 1 << 28  # numbers in one step's observations of a batch: 2 GiB of int64
MAX_NEAREST_K = 1024  # "nearest": other robots in a row (2 numbers each); fewer racing: the rest marked missing

ACTION_HELP = ", ".join(f"{a.value}={a.name}" for a in Action)


def as_int(value: object) -> int | None:
    """THE integer rule: ``value`` as a Python int if it is an integer (Python or numpy, or a 0-d
    integer array), else None: bools, floats (even ``3.0``) and strings are not integers."""
    if isinstance(value, (bool, np.bool_)):
        return None
    try:
        return operator.index(value)  # int, numpy integers, 0-d integer arrays; not float, not str
    except TypeError:
        return None


def _fail(message: str, name: str, value: object, **fields: Any) -> ValueError:
    return ValueError(message.format(name=name, value=repr(value) if _reprable(value) else shown(value),
                                     shown=shown(value), **fields))


def _reprable(value: object) -> bool:
    try:
        repr(value)
    except ValueError:  # an int of over 4,300 digits
        return False
    return True


def check_int(
    value: object, name: str, lo: int | None = None, hi: int | None = None, *, message: str | None = None
) -> int:
    """``value`` as a Python int in ``lo..hi`` (either bound may be None); else a ``ValueError`` naming ``name``.

    Python and numpy integers (and 0-d integer arrays) are accepted; bools, floats and strings are not.
    """
    v = as_int(value)
    if v is None or (lo is not None and v < lo) or (hi is not None and v > hi):
        if message is not None:
            raise _fail(message, name, value, lo=lo, hi=hi)
        raise ValueError(f"{name}: must be {_int_range(lo, hi)}, got {shown(value)}")
    return v


def check_count(value: object, name: str, most: int | None = None, *, message: str | None = None) -> int:
    """A size or count (``n_robots``, ``n_envs``, ``max_steps``, a side): an integer >= 1 (at most ``most``)."""
    return check_int(value, name, 1, most, message=message)


def check_real(
    value: object,
    name: str,
    lo: float | None = None,
    hi: float | None = None,
    *,
    open_lo: bool = False,
    message: str | None = None,
) -> float:
    """``value`` as a finite Python float in ``[lo, hi]`` (``(lo, hi]`` with ``open_lo``); else a
    ``ValueError`` naming ``name``.

    Python and numpy reals are accepted (integers too, when they fit a float); bools, complex
    numbers, strings and non-finite values are not.
    """
    f: float | None = None
    if isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)):
        try:
            f = float(value)
        except (OverflowError, ValueError):  # 10**400 does not fit a float
            f = None
    below = lo is not None and f is not None and (f <= lo if open_lo else f < lo)
    if f is None or not math.isfinite(f) or below or (hi is not None and f > hi):
        if message is not None:
            raise _fail(message, name, value, lo=lo, hi=hi)
        low, high = "-inf" if lo is None else lo, "inf" if hi is None else hi
        bounds = "" if lo is None and hi is None else f" in {'(' if open_lo else '['}{low}, {high}]"
        raise ValueError(f"{name}: must be a finite number{bounds}, got {shown(value)}")
    return f


def check_choice(value: object, name: str, choices: Collection[Any], *, none: bool = False, message: str | None = None) -> Any:
    """``value`` if it is one of ``choices`` (or None, with ``none``); else a ``ValueError`` naming ``name``."""
    try:
        ok = (none and value is None) or value in choices
    except TypeError:  # an unhashable value asked of a set
        ok = False
    if not ok:
        listed = ", ".join(map(repr, choices))
        if message is not None:
            raise _fail(message, name, value, choices=listed)
        raise ValueError(f"{name}: must be {'None or ' if none else ''}one of {listed}, got {value!r}")
    return value


def check_seed(seed: object, name: str = "seed", *, message: str | None = None) -> int | None:
    """``reset(seed=...)``: None or a non-negative integer (Python or numpy; bools and floats are not seeds)."""
    if seed is None:
        return None
    v = as_int(seed)
    if v is None or v < 0:
        raise _fail(message or "{name}: must be None or a non-negative integer, got {value}", name, seed)
    return v


def check_action(action: object, what: str = "action") -> int:
    """An action as a Python int in 0..4; anything else is a ``ValueError`` naming ``what``."""
    if type(action) is not int:
        if isinstance(action, (bool, np.bool_)) or getattr(getattr(action, "dtype", None), "kind", "") == "b":
            raise ValueError(f"{what}: expected an integer action ({ACTION_HELP}), got the bool {action!r}")
        try:
            action = operator.index(action)  # numpy integers and 0-d integer arrays
        except TypeError:
            raise ValueError(
                f"{what}: expected an integer action ({ACTION_HELP}), got {action!r} of type {type(action).__name__}"
            ) from None
    if not 0 <= action < N_ACTIONS:
        raise ValueError(f"{what}: must be an integer in 0..{N_ACTIONS - 1} ({ACTION_HELP}), got {action}")
    return action


def unexpected_keyword(owner: str, name: object, known: Sequence[str], rule_names: Collection[str] = ()) -> TypeError:
    """Python's own ``TypeError`` for an unknown keyword argument, followed by the known ones."""
    where = f"{owner}.__init__()" if owner else "__init__()"
    text = f"{where} got an unexpected keyword argument {name!r}"
    if known:
        text += f"; arguments are {', '.join(known)}"
    if rule_names:
        text += f"; rule overrides are {', '.join(sorted(rule_names))}"
    return TypeError(text)


def real_array(value: object, name: str) -> np.ndarray:
    """``value`` as a float64 array, if it holds real numbers only (ints, floats; numpy's too).

    Bools, complex numbers and strings (even numeric ones such as ``"1.5"``) are a ``ValueError``
    naming ``name``: ``np.array(value, dtype=float)`` alone would take ``"1.5"`` and drop ``1j``.
    """
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):  # ragged nesting
        raise ValueError(f"{name}: expected an array of numbers, got {shown(value)}") from None
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"{name}: expected real numbers (ints or floats), got an array of dtype {arr.dtype}")
    return arr.astype(np.float64)


def check_level_size(width: int, height: int, what: str = "width, height") -> None:
    """A level of ``width x height`` cells is within ``MAX_LEVEL_CELLS``."""
    if width * height > MAX_LEVEL_CELLS:
        raise ValueError(
            f"{what}: a level has at most {MAX_LEVEL_CELLS:,} cells (e.g. 256x256, or a one-row corridor "
            f"{MAX_LEVEL_CELLS:,} cells long), got {width}x{height} = {width * height:,}"
        )


def check_dense_states(n_states: int, width: int, height: int, what: str = "P") -> None:
    """A dense ``P[s, a, s']`` of ``n_states`` states is within ``MAX_DENSE_STATES`` (checked before allocating it)."""
    if n_states > MAX_DENSE_STATES:
        raise ValueError(
            f"{what}: the dense model holds at most {MAX_DENSE_STATES:,} states ({5 * 8 * MAX_DENSE_STATES**2 / 1e6:,.0f} MB); "
            f"this {width}x{height} level has {n_states:,} and would need {5 * 8 * n_states**2 / 1e9:,.1f} GB. "
            "Use the sparse model instead: model.next, model.prob and model.reward (value_iteration and the "
            "other planning functions read those)"
        )


def check_batch(n_envs: int, n_robots: int, obs_size: int, what: str = "n_envs") -> None:
    """A batch of ``n_envs`` races of ``n_robots``, observations of ``obs_size`` numbers a robot, is
    within the limits (checked before anything per env exists); ``what`` names the env count argument."""
    if n_envs > MAX_BATCH_ENVS:
        raise ValueError(
            f"{what}: a batch holds at most {MAX_BATCH_ENVS:,} envs (each keeps its own random generator), "
            f"got {n_envs:,}; step several batches instead"
        )
    if n_envs * n_robots > MAX_BATCH_ROBOTS:
        raise ValueError(
            f"{what}, n_robots: a batch holds at most {MAX_BATCH_ROBOTS:,} robots in all (n_envs * n_robots), "
            f"got {n_envs:,} x {n_robots:,} = {n_envs * n_robots:,}; use fewer envs or robots"
        )
    numbers = n_envs * n_robots * obs_size
    if numbers > MAX_BATCH_OBS:
        raise ValueError(
            f"{what}, n_robots: one step's observations would be {n_envs:,} x {n_robots:,} x {obs_size:,} = {numbers:,} "
            f"numbers ({8 * numbers / 2**30:,.1f} GiB), more than the limit of {MAX_BATCH_OBS:,} (2 GiB of int64); "
            "use fewer envs or robots, or observe='local' or 'nearest' (rows that do not grow with the robots)"
        )


def check_global_view(n_robots: int) -> None:
    """One race's "global" observations (every robot sees every other: ``n * (3n - 1)`` numbers a
    step, and an index as large) are within ``MAX_BATCH_OBS`` (checked before either exists)."""
    numbers = n_robots * (3 * n_robots - 1)
    if numbers > MAX_BATCH_OBS:
        raise ValueError(
            f"n_robots: with observe='global' each of {n_robots:,} robots sees every other, {numbers:,} numbers a step, "
            f"past the limit of {MAX_BATCH_OBS:,}; use observe='local' or 'nearest'"
        )


def check_view_radius(value: object, width: int, height: int, least: int = 2) -> int:
    """"local"'s ``view_radius`` as an int in ``0..max(width - 1, height - 1, least)``: a radius of
    ``max(width, height) - 1`` sees the whole level from any cell, a larger one only more outside
    (``least``: the default radius, allowed on the smallest levels too)."""
    top = max(width - 1, height - 1, least)
    try:
        return check_int(value, "view_radius", 0, top)
    except ValueError as err:
        raise ValueError(f"{err}; a radius of {top} sees the whole {width}x{height} level from any cell") from None


def check_nearest_k(value: object) -> int:
    """"nearest"'s ``k`` as an int in ``1..MAX_NEAREST_K`` (more than the other robots is allowed: the
    missing ones are marked so)."""
    try:
        return check_int(value, "k", 1, MAX_NEAREST_K)
    except ValueError as err:
        raise ValueError(f"{err} (the nearest other robots a robot sees)") from None


def check_view_numbers(n_robots: int, obs_size: int, what: str) -> None:
    """One race's "local" or "nearest" observations, ``n_robots`` rows of ``obs_size`` numbers a step,
    are within ``MAX_BATCH_OBS`` (checked before they exist); ``what`` names the size argument."""
    numbers = n_robots * obs_size
    if numbers > MAX_BATCH_OBS:
        raise ValueError(
            f"{what}, n_robots: {n_robots:,} robots seeing {obs_size:,} numbers each make {numbers:,} numbers a step, "
            f"past the limit of {MAX_BATCH_OBS:,}; use a smaller {what} or fewer robots"
        )


def _int_range(lo: int | None, hi: int | None) -> str:
    if lo is not None and hi is not None:
        return f"an integer in {lo}..{hi}"
    if lo is not None:
        return f"an integer >= {lo}"
    if hi is not None:
        return f"an integer <= {hi}"
    return "an integer"


def shown(value: object, limit: int = 60) -> str:
    """``repr(value)``, cut short: an error message never echoes a huge input in full."""
    try:
        text = repr(value)
    except ValueError:  # int too large to convert to str (over 4,300 digits)
        if isinstance(value, int):
            return f"an integer of about {value.bit_length() * 0.30103:.0f} digits"
        return type(value).__name__
    return text if len(text) <= limit else f"{text[: limit - 15]}...{text[-12:]} ({len(text):,} characters)"

