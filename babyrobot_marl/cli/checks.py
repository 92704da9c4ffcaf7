"""The command line's checks. Argument types: each turns one command-line string into a checked
value or raises ``argparse.ArgumentTypeError`` with a one-line reason (argparse then exits with
status 2). Bad text of any length or digit count gets this reason, never a traceback. Then the
checks across arguments (``check_train_args``): a ``ValueError`` naming the flag, before any long work.
"""

from __future__ import annotations

import argparse
import math
import os
import shlex
from collections.abc import Callable
from typing import Any

from .. import policies
from ..core.checks import check_batch, shown
from ..levels.sources import parse_level_family
from ..training.checks import MAX_LAYER_SIZE, MAX_LAYERS

MAX_RACES = 100_000  # races of one `race --races N`: run one after another, each kept for the table


def int_in(minimum: int, maximum: int | None = None, why: str = "") -> Callable[[str], int]:
    """An argparse type: an integer in ``minimum..maximum`` (no maximum: ``>= minimum``); ``why`` says
    where the maximum comes from."""
    allowed = f"an integer >= {minimum}" if maximum is None else f"an integer in {minimum}..{maximum:,}{why}"

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:  # not an integer, or more than Python's 4,300 digits
            value = minimum - 1
        if value < minimum or (maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(f"must be {allowed}, got {shown(text)}")
        return value

    return parse


def int_at_least(minimum: int) -> Callable[[str], int]:
    """An argparse type: an integer >= ``minimum``."""
    return int_in(minimum)


non_negative_int = int_at_least(0)
positive_int = int_at_least(1)

# a seed of any command and backend: NumPy's legacy seeding (Stable-Baselines3) takes seeds below 2**32
MAX_SEED = 2**32 - 1
seed_int = int_in(0, MAX_SEED, " (a seed below 2**32)")
SEED_HELP = "0 <= N < 2**32"

# `race --races N`: every race is kept for the metrics table, one after another
race_count = int_in(1, MAX_RACES, " (races run one after another: split a larger experiment into seeded runs)")


def real_in(ok: Callable[[float], bool], allowed: str) -> Callable[[str], float]:
    """An argparse type: a number for which ``ok`` holds (``nan`` never does); else "must be ``allowed``"."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not ok(value):
            raise argparse.ArgumentTypeError(f"must be {allowed}, got {shown(text)}")
        return value

    return parse


seconds = real_in(lambda v: 0.0 <= v < math.inf, "a number of seconds >= 0")  # nan, inf, negative delays: no animation
probability = real_in(lambda v: 0.0 < v <= 1.0, "a number in (0, 1]")
positive_float = real_in(lambda v: 0.0 < v < math.inf, "a number > 0")
non_negative_float = real_in(lambda v: 0.0 <= v < math.inf, "a number >= 0")
unit_real = real_in(lambda v: 0.0 <= v <= 1.0, "a number in [0, 1]")  # a discount, GAE's lambda


def output_path(text: str) -> str:
    """A file to write after a long run (``train --save``, ``--gif``, ``--curve``): its folder must exist
    and be writable now, and the path must not be a folder, so that nothing is lost at the end."""
    folder = os.path.dirname(text) or "."
    try:
        is_dir, folder_ok, writable = os.path.isdir(text), os.path.isdir(folder), os.access(folder, os.W_OK)
    except (OSError, ValueError):  # a NUL byte, a name too long
        is_dir, folder_ok, writable = False, False, False
    if not text or is_dir:
        raise argparse.ArgumentTypeError(f"must be a file's path, got {shown(text)}" + (" (a folder)" if is_dir else ""))
    if not folder_ok:
        raise argparse.ArgumentTypeError(f"no such folder {shown(folder)} for {shown(text)}; create it first")
    if not writable:
        raise argparse.ArgumentTypeError(f"the folder {shown(folder)} is not writable")
    return text


def level_spec(text: str) -> str:
    """``--level``: a name, a file or a family spec ``maze:A..B``; a malformed family spec is refused
    here, before any work (the level itself is read by the command)."""
    try:
        parse_level_family(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err).removeprefix("level: ")) from None
    return text


def _policy_problem(text: str, scripted: tuple[str, ...]) -> str | None:
    """Why ``text`` names no policy a command takes (``scripted`` names, or a saved policy's file), or None."""
    if text in scripted:
        return None
    try:
        is_dir, is_file = os.path.isdir(text), os.path.isfile(text)
    except (OSError, ValueError):  # a NUL byte, a name too long for a path
        is_dir, is_file = False, False
    if is_file:
        return None
    choices = (f"{', '.join(scripted)} or " if scripted else "") + "the path of a policy saved by 'train --save'"
    if is_dir:
        return f"{shown(text)} is a folder, not a saved policy; give {choices}"
    if text == "keys":
        return f"'keys' (you at the keyboard) is for 'play --policy' and 'race --human'; give {choices}"
    if os.sep in text or "." in text:  # meant as a file
        return f"no such file {shown(text)}; give {choices}"
    return f"unknown policy {shown(text)}; give {choices}"


def policy_file(text: str) -> str:
    """``train --load``: the path of a saved policy, which must exist now."""
    problem = _policy_problem(text, ())
    if problem:
        raise argparse.ArgumentTypeError(problem if "folder" in problem else f"no such file {shown(text)}")
    return text


def policy_spec(text: str) -> str:
    """``play --policy``: a scripted policy, ``keys`` (you drive), or the path of a saved policy."""
    problem = _policy_problem(text, (*policies.POLICY_NAMES, "keys"))
    if problem:
        raise argparse.ArgumentTypeError(problem)
    return text


def crowd_policy(text: str) -> str:
    """``evaluate POLICY``: a scripted policy or the path of a saved policy (no keyboard: nobody plays 200 episodes)."""
    problem = _policy_problem(text, tuple(policies.POLICY_NAMES))
    if problem:
        raise argparse.ArgumentTypeError(problem)
    return text


def policy_list(text: str) -> list[str]:
    """``race --policies``: scripted policy names or saved policies' paths, comma-separated."""
    names = [p.strip() for p in text.split(",")]
    for name in names:
        problem = _policy_problem(name, tuple(policies.POLICY_NAMES))
        if problem:
            raise argparse.ArgumentTypeError(f"{problem} (a comma-separated list, one per robot or one for all)")
    return names


def policies_form(names: list[str]) -> dict[str, Any]:
    """The env arguments of the observations the saved policies among ``names`` read (``{}``: the env's
    default); ``--policies`` that read different local windows cannot share one race."""
    from ..training.policy import observation_kwargs

    forms = {path: observation_kwargs(path) for path in dict.fromkeys(names) if path not in policies.POLICY_NAMES}
    local = {path: form for path, form in forms.items() if form}
    if len({tuple(form.items()) for form in local.values()}) > 1:
        (a, fa), (b, fb) = list(local.items())[:2]
        raise ValueError(f"--policies: one race shows one observation form; {a} reads {_as_flags(fa)}, {b} reads {_as_flags(fb)}")
    return next(iter(local.values()), {})


def _as_flags(form: dict[str, Any]) -> str:
    """A saved policy's observation form in the race's flags: ``--observe local --view-radius 2 --hint``."""
    flags = {f"--{k.replace('_', '-')}": v for k, v in form.items() if v is not False}
    return " ".join(flag if v is True else f"{flag} {v}" for flag, v in flags.items())


def layer_sizes(text: str) -> tuple[int, ...]:
    """``--net-arch``: hidden layer sizes such as ``64,64``, within ``MAX_LAYERS`` layers of ``MAX_LAYER_SIZE``."""
    try:
        sizes = tuple(int(s) for s in text.split(",") if s.strip()) if len(text) < 1000 else (0,)
    except ValueError:
        sizes = (0,)
    if not sizes or min(sizes) < 1 or max(sizes) > MAX_LAYER_SIZE or len(sizes) > MAX_LAYERS:
        raise argparse.ArgumentTypeError(f"must be layer sizes such as 64,64: 1 to {MAX_LAYERS} layers of 1..{MAX_LAYER_SIZE:,} "
                                         f"units, got {shown(text)}")
    return sizes


def check_train_args(args: argparse.Namespace, n_envs: int, family: bool = False) -> None:
    """What ``train``'s argument types cannot check alone, before any training (errors name the flags);
    ``n_envs``: the envs of one rollout of the chosen backend; ``family``: ``--level`` is a level family."""
    if (args.steps is None) == (args.seconds is None):
        raise ValueError("--seconds: give either --steps N (timesteps) or --seconds SECONDS (a wall-clock budget), "
                         f"not {'both' if args.steps is not None else 'neither'}")
    fast_only = [flag for flag, on in (("--seconds", args.seconds is not None), ("--observe local", args.observe == "local"),
                                       ("--collisions", args.collisions is not None)) if on]
    if args.backend != "fast" and fast_only:
        raise ValueError(f"{fast_only[0]}: only the fast backend has it; drop it or use --backend fast")
    if family and args.observe != "local":
        raise ValueError(f"--observe: a level family ({args.level}) trains a policy that reads local windows (its [x, y] "
                         "mean another place on every maze): pass --observe local")
    for flag, on in (("--hint", args.hint), ("--view-radius", args.view_radius is not None), ("--memory", args.memory),
                     ("--trail", args.trail), ("--recurrent", args.recurrent), ("--imitate", args.imitate is not None)):
        if on and args.observe != "local":
            raise ValueError(f"{flag}: only with --observe local (the local window's goal hint and radius, the last action, "
                             "the trail, a recurrent net, a crowd imitating a planner)")
    if args.imitate is not None:
        check_imitate_flags(args)
    for flag, given, what in (("--hidden", args.hidden, "size"), ("--cell", args.cell, "kind")):
        if given is not None and not args.recurrent:
            raise ValueError(f"{flag}: the recurrent cell's {what}, only with --recurrent; add --recurrent or drop {flag}")
    if args.max_cycles is not None and args.robots == 1:
        raise ValueError("--max-cycles: a race's step limit; a lone robot (--robots 1) has its level's, drop --max-cycles")
    if args.collisions is not None and args.robots == 1:
        raise ValueError("--collisions: a lone robot (--robots 1) meets nobody; drop --collisions or race --robots 2 or more")
    if args.observe == "local" and args.load:
        raise ValueError("--load: continuing from a saved policy is for --observe global; drop --load")
    if args.observe == "local" and args.gif:
        path = shlex.quote(args.save or "POLICY.pt")
        raise ValueError(f"--gif: not for --observe local; train without it, then watch the saved policy with 'babyrobot-marl "
                         f"race --level {shlex.quote(args.level)} --robots {args.robots} --start random --policies {path}'")
    if args.algo == "dqn" and (args.backend != "sb3" or args.robots > 1):
        raise ValueError("--algo dqn: only for one robot with --backend sb3")
    if args.robots > 1 and args.gif:
        raise ValueError("--gif: a GIF is written for one robot only; drop --gif for a race")
    if args.load and args.backend != "fast":
        raise ValueError("--load: starting from a saved policy needs --backend fast")
    if args.near_radius is not None and args.backend != "fast":
        raise ValueError("--near-radius: only the fast backend's race input has it; drop it or use --backend fast")
    if args.near_radius is not None and args.robots == 1:
        raise ValueError(f"--near-radius: a lone robot (--robots 1) sees no other robot; drop --near-radius or race "
                         f"--robots 2 or more (--near-radius {args.near_radius})")
    if args.blocked_cost is not None and args.backend != "fast":
        raise ValueError("--blocked-cost: only the fast backend trains with it; drop it or use --backend fast")
    if args.blocked_cost is not None and args.robots == 1:
        raise ValueError(f"--blocked-cost: a lone robot (--robots 1) is never stopped by another; drop --blocked-cost or "
                         f"race --robots 2 or more (--blocked-cost {args.blocked_cost:g})")
    n, obs = args.robots, 3 * args.robots - 1 if args.robots > 1 else 2  # the envs' global rows
    check_batch(n_envs, n, obs, what="--n-envs")
    # the final evaluation plays its episodes (races) at once in one batch: one rule for every robot count
    check_batch(args.episodes or 200, n, obs, what="--episodes")


_PPO_ONLY = ("n_envs", "n_steps", "gamma", "gae_lambda", "clip_range", "ent_coef", "blocked_cost")  # no imitation reads them


def check_imitate_flags(args: argparse.Namespace) -> None:
    """``--imitate``: PIBT's task (a crowd of own goals that stays on its targets, POGEMA's soft rule) and a
    feed-forward net on the fast backend."""
    need = [flag for flag, ok in (("--goals own", args.goals == "own"), ("--robots 2 or more", args.robots > 1),
                                  ("--collisions soft", args.collisions == "soft"), ("--finished stay", args.finished == "stay"))
            if not ok]
    if need:
        raise ValueError(f"--imitate: PIBT plans for a crowd of own goals that stays on its targets under POGEMA's rule; "
                         f"add {', '.join(need)}")
    refused = [flag for flag, on in (("--lifelong", args.lifelong), ("--trail", args.trail), ("--recurrent", args.recurrent),
                                     ("--backend sb3", args.backend != "fast")) if on]
    refused += [f"--{name.replace('_', '-')}" for name in _PPO_ONLY if getattr(args, name, None) is not None]
    if refused:
        raise ValueError(f"--imitate: learns a feed-forward net of the window, the hint, the last action and the "
                         f"neighbours' intents on the fast backend, by supervised passes (--lr, --batch-size, --n-epochs, "
                         f"--net-arch); drop {refused[0]}")


_RACE_FLAGS = {"n_robots": "--robots", "level": "--level", "collisions": "--collisions"}


def check_race_flags(level: str, robots: int, collisions: str, goals: str = "exit", lifelong: bool = False,
                     finished: str = "remove") -> None:
    """The race's own checks (robots that fit on the level, the level itself, the goals it can have) before any
    episode, naming the flags."""
    from ..envs.race import RaceEnv

    try:
        RaceEnv(level=level, n_robots=robots, collisions=collisions, start="random", observe="nearest", k=1, goals=goals,
                lifelong=lifelong, finished=finished)
    except ValueError as err:
        name, _, rest = str(err).partition(":")
        rest = rest.replace(" on level '',", " on this --level,")  # a grid map has no name
        raise ValueError(f"{_RACE_FLAGS[name]}:{rest}" if name in _RACE_FLAGS else str(err)) from None


def check_goal_flags(goals: str, lifelong: bool) -> None:
    """``--lifelong`` needs ``--goals own``: new targets replace reached ones."""
    if lifelong and goals != "own":
        raise ValueError("--lifelong: new targets replace reached ones, so it needs --goals own")


def check_finished_flag(goals: str, lifelong: bool, finished: str) -> None:
    """``--finished stay`` keeps robots on their own targets: it needs ``--goals own`` without ``--lifelong`` (said
    as the race's own check says it, by flag)."""
    if finished == "stay" and (goals != "own" or lifelong):
        got = "--lifelong" if goals == "own" else f"--goals {goals}"
        raise ValueError(f"--finished: 'stay' keeps robots on their own targets (--goals own, no --lifelong), got {got}")


# what a run's robots go for, by --goals: how an error names a saved policy's task and this run's
GOAL_TASKS = {"exit": "the race to the exits (--goals exit)", "own": "own targets (--goals own)"}


def trained_goals(name: str) -> str | None:
    """What the saved policy at ``name`` was trained for: ``"own"`` when its file records own goals (in the
    observation form it reads, or the env settings it trained under), else ``"exit"``, the race to the exits;
    None for a scripted policy or your keys (any task)."""
    from ..training.policy import load_checkpoint

    if name in (*policies.POLICY_NAMES, "keys"):
        return None
    data = load_checkpoint(name)
    for where in (data.get("observation"), data.get("env")):
        if isinstance(where, dict) and where.get("goals") in GOAL_TASKS:
            return where["goals"]
    return "exit"


def _saved_env(name: str) -> dict:
    """The env settings a saved policy at ``name`` records (``{}``: none recorded, a scripted policy, your keys)."""
    from ..training.policy import load_checkpoint

    if name in (*policies.POLICY_NAMES, "keys"):
        return {}
    env = load_checkpoint(name).get("env")
    return env if isinstance(env, dict) else {}


def trained_finished(name: str) -> str:
    """The rule the saved policy at ``name`` was trained under at its target: ``"stay"`` when its file records
    ``finished: stay``, else ``"remove"`` (files from before the rule was recorded, scripted policies, your keys)."""
    return "stay" if _saved_env(name).get("finished") == "stay" else "remove"


def trained_collisions(name: str) -> str:
    """The collision rule the saved policy at ``name`` was trained under (its file's ``env``), else ``"block"``
    (the race's default; scripted policies, your keys)."""
    return _saved_env(name).get("collisions", "block")


def check_policy_goals(names: list[str], goals: str, flag: str) -> None:
    """Each saved policy among ``names`` was trained for ``goals`` (the robots' task changes what they read and do)."""
    for name in dict.fromkeys(names):
        trained = trained_goals(name)
        if trained is not None and trained != goals:
            raise ValueError(f"{flag}: {name} was trained for {GOAL_TASKS[trained]}, not for {GOAL_TASKS[goals]}; "
                             f"pass --goals {trained}, or a policy trained with --goals {goals}")


def check_play_flags(args: argparse.Namespace) -> None:
    """``play``'s checks across flags: other robots and their collision rule only come with own goals."""
    check_goal_flags(args.goals, args.lifelong)
    if args.goals != "own" and args.robots > 1:
        raise ValueError(f"--robots: play drives one robot to the exit; other robots come with --goals own (or watch "
                         f"a race: babyrobot-marl race --robots {args.robots})")
    if args.collisions is not None and args.robots == 1:
        raise ValueError(f"--collisions: a lone robot (--robots 1) meets nobody; drop --collisions or play among "
                         f"--robots 2 or more with --goals own (--collisions {args.collisions})")
    check_policy_goals([args.policy], args.goals, "--policy")


def check_race_gif(args: argparse.Namespace) -> None:
    """``--gif``: one race with frames (not ``--races``, not your keys), and imageio at hand, before the race."""
    if args.races:
        raise ValueError("--gif: a GIF shows one race; drop --races (N races without frames) or --gif")
    if args.human is not None:
        raise ValueError("--gif: not for a race you drive (--human); drop --gif or --human")
    try:
        import imageio  # noqa: F401
    except ImportError:
        raise ValueError("--gif: needs imageio: pip install 'babyrobot_marl[video]'") from None


def check_train_goals(args: argparse.Namespace) -> None:
    """``train``'s own goals: the fast trainer's policies that read local windows learn them (the target channel
    and the hint toward it); ``--lifelong`` needs them."""
    check_goal_flags(args.goals, args.lifelong)
    check_finished_flag(args.goals, args.lifelong, args.finished)
    if args.goals == "own" and args.backend != "fast":
        raise ValueError("--goals own: only the fast backend trains own goals; drop --backend sb3")
    if args.goals == "own" and args.observe != "local":
        raise ValueError("--goals own: a robot reads its own target in its local window: pass --observe local")
