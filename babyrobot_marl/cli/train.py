"""``babyrobot-marl train``: the fast PPO trainer (default) or Stable-Baselines3 (``--backend sb3``).

::

    babyrobot-marl train --level maze-8x8 --steps 3000000 --save ppo.pt --curve curve.png
    babyrobot-marl train --level race-4 --robots 4 --steps 2000000      # one shared policy
    babyrobot-marl train --level maze-8x8 --steps 100000 --backend sb3 --save ppo.zip
    babyrobot-marl play --level maze-8x8 --policy ppo.pt                 # replay a saved policy

On a terminal a progress bar shows steps/s and the mean training return; elsewhere (a log, a
pipe) one line per evaluation. Every argument is checked before training (a ``--steps`` that
whole rollouts round up is said in one line first); a run whose loss or weights stop being finite
numbers ends with one error line and saves nothing; otherwise ``--save`` is written as soon as training
ends, before any evaluation. After training, one line gives the speed in
wall-clock and in CPU time. The LAST line is always one JSON object: ``env_steps_per_second``
(timesteps over wall-clock training seconds: rollouts and updates, evaluations excluded),
``timesteps``, ``seconds``, ``cpu_seconds`` and ``env_steps_per_cpu_second`` (the same over the
process's CPU time: on a busy machine wall time also counts the others), and for one robot
``optimal_return`` (value iteration), ``final_return`` (the greedy policy from the level's start),
``timesteps_to_95`` and ``seconds_to_95`` (the first evaluation within 5% of the optimum; null if
none); for a race ``win_rate`` against ``opponents`` (and the tie rate, and the rates against
shortest-path robots).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from typing import Any, TextIO

import numpy as np

from .. import training
from ..core.level import Level
from ..core.observe import DEFAULT_VIEW_RADIUS
from ..envs.single import BabyRobotEnv
from ..levels.files import load_level
from ..levels.sources import parse_level_family
from ..play.screen import isatty
from ..training.checks import CELL_NAMES, check_finite_sb3
from ..training.crowd import crowd_defaults, said
from ..training.deps import INSTALL_HINT
from .checks import check_race_flags, check_train_args, check_train_goals
from .train_args import FAST_ROLLOUT, KNOBS, SB3_RACE_ROLLOUT, SB3_ROLLOUT, add_train_arguments


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "train",
        help="train PPO (one robot, or one policy shared by a race's robots) and evaluate it (needs the 'train' extra)",
        description="One robot (--robots 1): PPO on BabyRobot-v0, evaluated greedily from the level's start against "
        "value iteration's optimum. Several robots: one PPO policy shared by all robots, then its win rate against "
        "'random' and 'shortest' robots. --backend fast (default) steps the batch engine directly; --backend sb3 "
        "trains Stable-Baselines3 (SuperSuit for a race). The last line printed is one JSON object of figures. "
        f"Needs the 'train' extra: {INSTALL_HINT}.",
    )
    add_train_arguments(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace, out: TextIO) -> int:
    family = parse_level_family(args.level)  # "maze:A..B": a new maze per episode
    level = family(np.random.default_rng(0)) if family is not None else load_level(args.level)
    check_train_args(args, _rollout(args)[0], family is not None)  # the user's mistakes first, with or without torch
    check_train_goals(args)
    if args.robots > 1 or args.goals == "own":  # robots that fit on the level, named by flag, before asking for torch
        check_race_flags(args.level, args.robots, args.collisions or "block", args.goals, args.lifelong,
                         args.finished)
    # a missing package: MissingTrainExtraError, one line from the CLI's main (exit 2); called through the
    # package (training.require_train), where tests put a stand-in
    training.require_train(*(("torch", "tqdm") if args.backend == "fast" else ()))
    chosen = {"near_radius": args.near_radius, "blocked_cost": args.blocked_cost}
    window = _view_radius(args) if args.observe == "local" else None
    args.crowd = crowd_defaults(args.robots, args.collisions, chosen, window) if args.backend == "fast" else {}
    if args.imitate is not None:  # a crowd that imitates a planner has no reward to shape
        args.crowd.pop("blocked_cost", None)
    tty = not args.no_progress and isatty(out) and isatty(sys.stderr)
    run = _family if family is not None else _fast if args.backend == "fast" else _sb3
    figures = run(args, level, tty, out)
    out.write(json.dumps(figures) + "\n")  # the last line: machine-readable figures
    return 0


def _view_radius(args: argparse.Namespace) -> int:
    """The window's radius a local-view policy reads: ``--view-radius``, else the env's default."""
    return DEFAULT_VIEW_RADIUS if args.view_radius is None else args.view_radius


def _rollout(args: argparse.Namespace) -> tuple[int, int, int]:
    """``(n_envs, n_steps, timesteps)`` of one rollout of the chosen backend; training runs whole rollouts
    (SB3's DQN steps one env: a rollout of one timestep)."""
    if args.backend == "sb3" and args.algo == "dqn":
        return 1, 1, 1
    envs, steps = FAST_ROLLOUT if args.backend == "fast" else SB3_ROLLOUT if args.robots == 1 else SB3_RACE_ROLLOUT
    if args.backend == "fast" and args.observe == "local":
        envs = FAMILY_ENVS
    envs, steps = args.n_envs or envs, args.n_steps or steps
    return envs, steps, envs * steps * args.robots


def _say_rounded_steps(args: argparse.Namespace, out: TextIO) -> None:
    """One line when whole rollouts round ``--steps`` up: the run trains the rounded count."""
    envs, steps, unit = _rollout(args)
    if args.steps is None or args.imitate is not None:  # --seconds, or imitation: whole rounds of episodes
        return
    total = -(-args.steps // unit) * unit
    if total != args.steps:
        robots = f" x {args.robots} robots" if args.robots > 1 else ""
        out.write(f"--steps {args.steps:,}: training runs whole rollouts of {unit:,} timesteps (--n-envs {envs} x "
                  f"--n-steps {steps}{robots}), so {total:,} timesteps\n")


def _knobs(args: argparse.Namespace) -> dict[str, Any]:
    chosen = {name: getattr(args, flag) for flag, (name, _) in KNOBS.items() if getattr(args, flag) is not None}
    if args.net_arch is not None:
        chosen["net_arch"] = args.net_arch
    return chosen


def _crowd_note(args: argparse.Namespace) -> str:
    """The crowd defaults this run trained with, for its summary line ("" if none)."""
    crowd = getattr(args, "crowd", {})
    return f"; crowd defaults {said(crowd)}" if crowd else ""


def _round(x: float | None, digits: int = 4) -> float | None:
    return None if x is None or not math.isfinite(x) else round(x, digits)


def _name(level: Level, args: argparse.Namespace) -> str:
    return level.name or args.level


# ---------------------------------------------------------------------------- the fast trainer
def _fast(args: argparse.Namespace, level: Level, tty: bool, out: TextIO) -> dict[str, Any]:
    from ..training.checks import TrainingDivergedError
    from ..training.policy import load_checkpoint, load_net
    from ..training.ppo.config import PPOConfig
    from ..training.ppo.loop import train_ppo
    from ..training.progress import TrainProgress

    knobs = _knobs(args)
    for name in ("eval_every", "near_radius", "blocked_cost"):
        if getattr(args, name) is not None:
            knobs[name] = getattr(args, name)
    config = PPOConfig(threads=args.threads or None, **knobs, **args.crowd)  # each knob checked by its flag's type
    if args.observe == "local":  # one level, the net reading its local windows: an atlas of that one level
        return _family(args, level, tty, out)
    init = None
    if args.load:
        data = load_checkpoint(args.load)
        if (data["width"], data["height"]) != (level.width, level.height) or (data["n_robots"] == 1) != (args.robots == 1):
            raise ValueError(f"--load: {args.load!r} was trained on a {data['width']}x{data['height']} level with "
                             f"{data['n_robots']} robot(s); this run is {level.width}x{level.height} with {args.robots}")
        init = load_net(data)
        # what the saved net was built for, unless given (a one-robot file of version 1 has no near_radius)
        if "net_arch" not in knobs:
            config = config.replace(net_arch=tuple(data["net_arch"]))
        if "near_radius" not in knobs and "near_radius" in data["config"]:
            config = config.replace(near_radius=data["config"]["near_radius"])
            args.crowd.pop("near_radius", None)  # the saved net's input, not the crowd's default
    _say_rounded_steps(args, out)  # every argument checked, the saved policy too
    single = args.robots == 1
    evaluate, target, score_name, finish = _single_eval(level, args) if single else _race_eval(level, args)
    progress = TrainProgress(args.steps or UNBOUNDED, tty, out, score_name, enabled=not args.no_progress)
    try:
        result = train_ppo(
            level, args.robots, args.steps or UNBOUNDED, args.seed, config, evaluate=evaluate, target=target, init=init,
            max_seconds=args.seconds, env_kwargs=_env_kwargs(args), on_trained=_keep(args),
            on_update=progress.update, on_eval=lambda p: progress.evaluation(p.timesteps, p.seconds, p.train_return, p.score),
        )
    except TrainingDivergedError as err:  # nothing is saved: the flag, the value and what to do, on one line
        raise ValueError(f"--lr {config.learning_rate:g}: {str(err).split(': ', 1)[1]}; nothing was saved") from None
    finally:
        progress.close()
    _save(args, lambda path: result.save(path), "policy", out)  # first: nothing after training can lose it
    agent = result.policy()
    figures = _speed(args, level, result.timesteps, result.seconds, result.cpu_seconds, out)
    reached = result.reached
    figures.update(finish(agent, out, args, reached))
    points = [(p.timesteps, p.train_return, p.score) for p in result.history]
    _outputs(args, level, agent, out, points, score_name, target)
    return figures


UNBOUNDED = 2**62  # timesteps of a run bounded by --seconds
# a family's default --n-envs: 4x the updates per timestep of 1,024 (maze:8..16 with the hint: 1.000 after 30 s,
# 0.05 after 20 s with 1,024)
FAMILY_ENVS = 256
FAMILY_EVAL_EVERY = 2**21  # a family's evaluations play whole races on the batch engine: fewer than one per rollout
EVAL_ATLASES = 8  # the final evaluation's atlases at most: large mazes fit few to an atlas, each played in turn


def _env_kwargs(args: argparse.Namespace) -> dict[str, Any]:
    kwargs: dict[str, Any] = {} if args.collisions is None else {"collisions": args.collisions}
    if args.max_cycles is not None:
        kwargs["max_cycles"] = args.max_cycles
    if args.goals == "own":  # each robot its own target (and a new one on reaching it, lifelong)
        kwargs.update(goals="own", lifelong=args.lifelong)
        if args.finished == "stay":  # robots stay on their targets, racing on (the default leaves them out)
            kwargs["finished"] = "stay"
    return kwargs


def _family(args: argparse.Namespace, level: Level, tty: bool, out: TextIO) -> dict[str, Any]:
    """The fast trainer on a level family (or one level) with the net reading local windows: an atlas of mazes
    on the batch engine (``training.ppo.window``), judged on mazes of the evaluation seeds."""
    from ..levels.sources import EVAL_MAZE_SEEDS
    from ..training.checks import TrainingDivergedError
    from ..training.ppo.config import PPOConfig
    from ..training.ppo.loop import train_ppo
    from ..training.ppo.window import Family, play_atlas
    from ..training.progress import TrainProgress

    knobs = _knobs(args)
    for name in ("near_radius", "blocked_cost"):
        if getattr(args, name) is not None:
            knobs[name] = getattr(args, name)
    knobs.update(args.crowd)
    knobs["eval_every"] = args.eval_every or FAMILY_EVAL_EVERY
    knobs.setdefault("n_envs", FAMILY_ENVS)
    config = PPOConfig(threads=args.threads or None, view_radius=_view_radius(args),
                       hint=args.hint, memory=args.memory, trail=args.trail, recurrent=args.recurrent, imitate=args.imitate,
                       hidden=args.hidden or 32, cell=args.cell or "gru", **knobs)
    one_level = parse_level_family(args.level) is None
    if one_level:  # an atlas of that one level
        config = config.replace(atlas_size=1)
    spec = (lambda rng: level) if one_level else args.level
    judge = Family((lambda rng: level) if one_level else parse_level_family(args.level, EVAL_MAZE_SEEDS), args.robots, config,
                   args.seed + 1, _env_kwargs(args))  # checks collisions, view_radius, hint before training
    _say_rounded_steps(args, out)
    episodes = args.episodes or 200

    along = judge.atlas(16)  # the evaluations along the way: 64 episodes on 16 unseen mazes
    greedy = args.imitate is None  # an imitation crowd acts sampled: greedy, robots that wait on each other wait for ever

    def evaluate(result: Any) -> float:
        score = play_atlas(result.net, along, args.robots, 64, judge.max_steps, np.random.default_rng(args.seed + 1),
                           greedy)
        return score.get("throughput", score["success_rate"])  # lifelong: nobody finishes, targets per step

    score_name = "throughput (unseen mazes)" if args.lifelong else "success rate (unseen mazes)"
    progress = TrainProgress(args.steps or UNBOUNDED, tty, out, score_name, enabled=not args.no_progress)
    try:
        result = train_ppo(spec, args.robots, args.steps or UNBOUNDED, args.seed, config, evaluate=evaluate,
                           max_seconds=args.seconds, env_kwargs=_env_kwargs(args), on_update=progress.update,
                           on_trained=_keep(args),
                           on_eval=lambda p: progress.evaluation(p.timesteps, p.seconds, p.train_return, p.score))
    except TrainingDivergedError as err:
        raise ValueError(f"--lr {config.learning_rate:g}: {str(err).split(': ', 1)[1]}; nothing was saved") from None
    finally:
        progress.close()
    _save(args, lambda path: result.save(path), "policy", out)  # first: nothing after training can lose it
    figures = _speed(args, level, result.timesteps, result.seconds, result.cpu_seconds, out)
    judge.rng = np.random.default_rng(args.seed + 1)  # up to 256 unseen mazes, in atlases that fit
    mazes = 1 if one_level else min(episodes, 256, EVAL_ATLASES * judge.atlas_capacity)
    score = judge.play(result.net, episodes, mazes, np.random.default_rng(args.seed + 2), greedy)
    where = _name(level, args) if one_level else f"{args.level}, mazes of the evaluation seeds"
    reads = f"view_radius {config.view_radius}{', hint' if config.hint else ''}{', memory' if config.memory else ''}"
    reads += ", trail" if config.trail else ""
    reads += f", {CELL_NAMES[config.cell]} of {config.hidden} units" if config.recurrent else ""
    reads += ", the near robots' intents, in turns" if config.imitate else ""
    reads += f", own goals{', lifelong' if args.lifelong else ''}" if args.goals == "own" else ""
    reads += ", finished stay" if args.finished == "stay" else ""
    reads += f", collisions {args.collisions}" if args.collisions else ""
    lifelong = f", throughput {score['throughput']:.3f} targets per step" if "throughput" in score else ""
    method = "imitation of PIBT" if config.imitate else "fast PPO"
    acting = "greedy" if greedy else "sampled"
    out.write(f"{method}, one policy for {args.robots} robot(s) reading local windows ({reads}{_crowd_note(args)}"
              f") on {where}: {episodes} episodes, {acting}: success rate {score['success_rate']:.3f}, "
              f"all reached {score['all_reached_rate']:.3f}, makespan {score['makespan']:.1f}{lifelong}\n")
    figures.update({k: _round(v) for k, v in score.items()})
    figures.update(level=_name(level, args) if one_level else args.level, episodes=episodes)
    points = [(p.timesteps, p.train_return, p.score) for p in result.history]
    _outputs(args, level, None, out, points, score_name, None)
    return figures


def _speed(args: argparse.Namespace, level: Level, timesteps: int, seconds: float, cpu: float, out: TextIO) -> dict[str, Any]:
    """The speed line (wall-clock and CPU time, each named) and the first JSON figures."""
    wall_rate, cpu_rate = timesteps / seconds if seconds > 0 else math.nan, timesteps / cpu if cpu > 0 else math.nan
    out.write(f"trained {timesteps:,} timesteps in {seconds:.2f} s wall-clock ({wall_rate:,.0f} env steps/s) and "
              f"{cpu:.2f} s of CPU time ({cpu_rate:,.0f} env steps/s of CPU time): rollouts and updates only\n")
    return {"backend": args.backend, "level": _name(level, args), "robots": args.robots, "timesteps": timesteps,
            "seconds": _round(seconds), "env_steps_per_second": _round(wall_rate, 1),
            "cpu_seconds": _round(cpu), "env_steps_per_cpu_second": _round(cpu_rate, 1)}


def _method(args: argparse.Namespace) -> str:
    """What trained, as the summary and the curve's title say it: e.g. "fast PPO", "sb3 DQN"."""
    return f"{args.backend} {args.algo.upper()}"


def _single_eval(level: Level, args: argparse.Namespace) -> tuple[Any, float, str, Any]:
    from ..training.single import evaluate_single, optimal_return

    env = BabyRobotEnv(level=level)
    optimum = optimal_return(env)
    target = optimum - 0.05 * abs(optimum)
    seed = args.seed + 1_000_000
    episodes = args.episodes or 20

    def evaluate(result: Any) -> float:
        return evaluate_single(result.policy(), env, episodes=5, seed=seed).mean

    def finish(agent: Any, out: TextIO, args: argparse.Namespace, reached: tuple[int, float] | None) -> dict[str, Any]:
        ev = evaluate_single(agent, env, episodes=episodes, seed=seed)
        out.write(f"{_method(args)} on {_name(level, args)}: greedy return {ev.mean:g} (+- {ev.std:g}, {ev.reached_exit}/"
                  f"{ev.episodes} reached the exit), optimal {optimum:g}; 95% of it "
                  + (f"first reached at {reached[0]} timesteps, {reached[1]:.2f} s\n" if reached else "not reached\n"))
        return {"optimal_return": _round(optimum), "final_return": _round(ev.mean),
                "timesteps_to_95": reached[0] if reached else None, "seconds_to_95": _round(reached[1]) if reached else None}

    return evaluate, target, "greedy return", finish


RACE_TARGET = 0.95  # win rate against random robots


def _race_eval(level: Level, args: argparse.Namespace) -> tuple[Any, float, str, Any]:
    from ..training.evaluate import race_rates

    n, seed = args.robots, args.seed + 1
    races = args.episodes or 100

    def evaluate(result: Any) -> float:
        return race_rates(result.policy(), level, n, "random", races=50, seed=seed, threads=args.threads or None).win_rate

    def finish(agent: Any, out: TextIO, args: argparse.Namespace, reached: tuple[int, float] | None) -> dict[str, Any]:
        rates = {o: race_rates(agent, level, n, o, races, seed, threads=args.threads or None) for o in ("random", "shortest")}
        return _race_figures(rates, level, args, out)

    return evaluate, RACE_TARGET, "win rate vs random", finish


def _race_figures(rates: dict[str, Any], level: Level, args: argparse.Namespace, out: TextIO) -> dict[str, Any]:
    """The race's lines and JSON figures from win and tie rates against each kind of opponent."""
    n = args.robots
    out.write(f"{args.backend} PPO, one policy for {n} robots on {_name(level, args)}{_crowd_note(args)}; robot_0 from the "
              f"level's start against {n - 1} scripted robots, {rates['random'].races} races each:\n")
    for opponent, res in rates.items():
        out.write(f"  vs {opponent}: win rate {res.win_rate:.3f} (ties included), tie rate {res.tie_rate:.3f}\n")
    r, s = rates["random"], rates["shortest"]
    return {"win_rate": _round(r.win_rate), "tie_rate": _round(r.tie_rate), "opponents": ["random"] * (n - 1),
            "races": r.races,
            "vs_shortest": {"win_rate": _round(s.win_rate), "tie_rate": _round(s.tie_rate), "opponents": ["shortest"] * (n - 1)}}


def _keep(args: argparse.Namespace) -> Any:
    """``--save``: the policy written the moment training ends, before the trainer's final evaluation (which
    can take minutes on large mazes); ``_save`` writes it again with that evaluation and says where."""
    return (lambda result: result.save(args.save)) if args.save else None


def _save(args: argparse.Namespace, save: Any, what: str, out: TextIO) -> None:
    """``--save``: the trained policy written as soon as training ends, before any evaluation."""
    if args.save:
        out.write(f"{what} saved to {save(args.save)}\n")


def _outputs(args: argparse.Namespace, level: Level, agent: Any, out: TextIO, points: list, score_name: str,
             target: float | None) -> None:
    """The GIF and the curve, each reported with the path it was written to."""
    if args.gif:
        from ..render.video import episode_frames, save_gif

        frames = episode_frames(BabyRobotEnv(level=level, render_mode="rgb_array"), agent, seed=args.seed)
        out.write(f"GIF of the learnt policy: {save_gif(frames, args.gif)}\n")
    if args.curve:
        from ..training.curve import save_curve

        if points:
            title = f"{_method(args)} on {_name(level, args)}" + (f", {args.robots} robots" if args.robots > 1 else "")
            out.write(f"learning curve saved to {save_curve(points, args.curve, score_name, target, title)}\n")
        else:
            out.write("no learning curve: no evaluation ran\n")


# ---------------------------------------------------------------------------- Stable-Baselines3
def _sb3(args: argparse.Namespace, level: Level, tty: bool, out: TextIO) -> dict[str, Any]:
    from ..training.ppo.loop import torch_threads
    from ..training.progress import TrainProgress, target_callback

    knobs = _knobs(args)
    ppo_kwargs = {k: v for k, v in knobs.items() if k not in ("n_envs", "net_arch")}
    if "net_arch" in knobs:
        ppo_kwargs["policy_kwargs"] = {"net_arch": list(knobs["net_arch"])}
    n_envs = knobs.get("n_envs")
    every = args.eval_every or 5000
    _say_rounded_steps(args, out)
    single = args.robots == 1
    with torch_threads(args.threads or None):
        if single:
            from ..training.single import evaluate_single, train_single

            evaluate, target, score_name, finish = _single_eval(level, args)
            progress = TrainProgress(args.steps, False, out, score_name, enabled=not args.no_progress and not tty)
            env = BabyRobotEnv(level=level)
            cb = target_callback(lambda m: evaluate_single(m, env, episodes=5, seed=args.seed + 1_000_000).mean, target,
                                 every=every, stop=False, on_eval=lambda t, s, m: progress.evaluation(t, s, cb.train_return, m))
            if "policy_kwargs" in ppo_kwargs:  # keep the one-hot cell features beside the chosen layers
                from ..training.single import cell_features_class

                w, h = level.width, level.height
                ppo_kwargs["policy_kwargs"].update(features_extractor_class=cell_features_class(),
                                                   features_extractor_kwargs={"width": w, "height": h})
            t0, c0 = time.perf_counter(), time.process_time()
            agent = train_single(level, args.algo, steps=args.steps, seed=args.seed, progress_bar=tty, callback=cb,
                                 env_kwargs={"start": "random"}, threads=args.threads or None,
                                 **({"n_envs": n_envs} if n_envs else {}), **ppo_kwargs)
            seconds = time.perf_counter() - t0 - cb._eval_seconds
            cpu = time.process_time() - c0 - cb._eval_cpu_seconds
            timesteps = int(agent.num_timesteps)
            reached = cb.reached
            points = [(t, float("nan"), m) for t, _, m in cb.history]
        else:
            from ..training.race import train_race

            t0, c0 = time.perf_counter(), time.process_time()
            agent = train_race(level, n_robots=args.robots, steps=args.steps, seed=args.seed, progress_bar=tty,
                               threads=args.threads or None, **({"n_envs": n_envs} if n_envs else {}), **ppo_kwargs)
            seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
            timesteps, reached, points, target, score_name = int(agent.num_timesteps), None, [], RACE_TARGET, "win rate vs random"
    check_finite_sb3(agent, args.lr)

    def save(path: str) -> str:
        with open(path, "wb") as f:  # an open file: SB3 writes exactly here (given a name, it appends .zip)
            agent.save(f)
        return path

    _save(args, save, "model", out)  # first: nothing after training can lose it
    figures = _speed(args, level, timesteps, seconds, cpu, out)
    if single:
        figures.update(finish(agent, out, args, reached))
    else:
        from ..training.race import evaluate_race

        races = args.episodes or 100
        rates = {o: evaluate_race(agent, level, n_robots=args.robots, opponent=o, races=races, seed=args.seed + 1, start="fill")
                 for o in ("random", "shortest")}
        figures.update(_race_figures(rates, level, args, out))
    if args.curve and not points:
        out.write("no learning curve: the sb3 race backend runs no evaluations while training\n")
        args.curve = None

    def policy(obs: Any) -> int:
        return int(agent.predict(obs, deterministic=True)[0])

    _outputs(args, level, policy, out, points, score_name, target)
    return figures
