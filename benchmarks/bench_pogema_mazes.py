"""POGEMA's maze benchmark in this package: its 128 validation mazes, its starts and goals, its metrics.

    python benchmarks/bench_pogema_mazes.py            # 128 mazes x 8, 16, 32, 48, 64 robots
    python benchmarks/bench_pogema_mazes.py --quick    # 4 mazes, 8 robots (no POGEMA needed)
    python benchmarks/bench_pogema_mazes.py --pibt     # PIBT's crowd beside (a centralised planner)
    python benchmarks/bench_pogema_mazes.py --lacam    # LaCAM's plans beside (a search over PIBT's steps)
    python benchmarks/bench_pogema_mazes.py --policy FILE --shield   # a learnt crowd, alone and shielded by PIBT
    python benchmarks/bench_pogema_mazes.py --in-pogema --pogema-python PATH    # the same robots in POGEMA too
    python benchmarks/bench_pogema_mazes.py --regenerate --pogema-python PATH   # check the shipped data

The mazes (21x21 at most) and the starts and goals of POGEMA's benchmark (02-mazes, MAPF) ship in
``benchmarks/data/pogema_mazes.json``, made by ``pogema_mazes_data.py`` with pogema-toolbox's maze
generator and POGEMA 1.4's own start and goal generator (seed 0). Each maze is read with
``Level.from_grid`` and raced as ``race_v0.parallel_env(goals="own", collisions="soft",
max_cycles=128)``, the benchmark's starts and goals given by ``reset(options=...)``.

The robots are shortest-path robots: each follows a shortest path to its own goal as if alone (the
lowest-numbered action among the optimal ones, ``planning.goal_actions``), stops only when the
soft rule stops it. As in the published runs (POGEMA's ``on_target="nothing"``), a robot that
reaches its goal stays there and still blocks (``finished="stay"``), and an episode is solved when
every robot stands on its goal at once; ``--finished remove`` lets a robot leave the board at its
goal instead (POGEMA's ``on_target="finish"``). ``--in-pogema`` steps the same robots in POGEMA 1.4
itself (its own venv) with both: with the matching rule every episode must be the one run here,
robot by robot (else exit status 1).
Metrics are POGEMA's, named as ``babyrobot-marl evaluate`` names them:
``all_reached_rate`` (CSR), ``success_rate`` (ISR), ``sum_of_costs`` and ``makespan``, with 95%
intervals (Wilson for rates, over mazes for CSR and robots for ISR; normal for means).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from babyrobot_marl import race_v0
from babyrobot_marl.core.level import Level
from babyrobot_marl.experiments.evaluate import METRICS, Episode, arrivals, crowd_metrics
from babyrobot_marl.planning import PIBT, LaCAM, goal_actions

HERE = Path(__file__).resolve().parent
DATA = HERE / "data" / "pogema_mazes.json"
MAKER = HERE / "pogema_mazes_data.py"
STEPS = 128
ON_TARGET = {"stay": "nothing", "remove": "finish"}  # our finished= and POGEMA's on_target, the same rule
ROBOTS = (8, 16, 32, 48, 64)
QUICK_MAZES, QUICK_ROBOTS = 4, (8,)
LACAM_NODES = 20_000  # LaCAM's budget per episode, in PIBT steps tried (not time: same figures on any machine)
SUMMARY_LABELS = {"learnt": "learnt policy (ours)", "shielded": "learnt + PIBT shield (ours)",
                  "PIBT": "PIBT (ours, centralised)",
                  "LaCAM": "LaCAM (ours, centralised)"}  # other crowds' rows, by the start of their names
SOURCE = "POGEMA's benchmark results (2025), 128 validation mazes, 128 steps, soft collisions"
PUBLISHED = {  # CSR (all robots reached) at 32 / 64 robots
    "LaCAM": (1.00, 0.91),
    "MAPF-GPT-DDG": (1.00, 0.82),
    "MAPF-GPT-85M": (0.97, 0.70),
    "SCRIMP": (0.55, 0.15),
    "DCC": (0.36, 0.02),
}


def load_mazes(path: Path = DATA) -> list[dict]:
    """The shipped mazes: ``name``, ``grid`` (rows of ``.`` and ``#``) and per robot count its flat
    ``starts`` and ``goals`` (``[x0, y0, x1, y1, ...]``)."""
    return json.loads(path.read_text())["mazes"]


def cells(flat: list[int]) -> list[tuple[int, int]]:
    return list(zip(flat[0::2], flat[1::2]))


@lru_cache(maxsize=256)
def level_of(grid: str) -> Level:
    """The maze as a level, as it comes: no exit (each robot has its own target)."""
    return Level.from_grid(grid)


@lru_cache(maxsize=4096)
def path_actions(grid: str, goal: tuple[int, int]) -> np.ndarray:
    """``int[H, W]``: a shortest-path robot's action toward ``goal`` (the lowest optimal; STAY on it)."""
    best = goal_actions(level_of(grid), goal)
    return np.where(best.any(axis=2), best.argmax(axis=2), 0)


def race(grid: str, starts: list[tuple[int, int]], goals: list[tuple[int, int]], finished: str = "stay",
         planner: str | None = None, nodes: int = LACAM_NODES) -> Episode:
    """One episode of shortest-path robots (``planner``: ``"pibt"`` or ``"lacam"``, that planner's moves
    instead; ``nodes``: LaCAM's budget): each robot's arrival step (0: not on its goal at the end)."""
    env = race_v0.parallel_env(level=level_of(grid), n_robots=len(starts), goals="own", collisions="soft",
                               observe="nearest", k=1, start="random", max_cycles=STEPS, finished=finished)
    env.reset(seed=0, options={"starts": starts, "goals": goals})
    plans = None if planner is None else planner_of(planner, grid, goals, nodes)
    tables = None if plans is not None else [path_actions(grid, g) for g in goals]
    finish = [0] * len(starts)
    names = {a: i for i, a in enumerate(env.possible_agents)}
    t = 0
    while env.agents:
        t += 1
        cells = env.robot_cells
        chosen = plans.actions(cells) if plans is not None else [int(tab[y, x]) for tab, (x, y) in zip(tables, cells)]
        arrivals(finish, env.step({a: chosen[names[a]] for a in env.agents})[4], names, t)
    return Episode(seed=0, level=grid, steps=t, finish_steps=finish)


def planner_of(name: str, grid: str, goals: list[tuple[int, int]], nodes: int = LACAM_NODES) -> PIBT | LaCAM:
    """The planner ``name`` (``"pibt"`` or ``"lacam"``) for one episode; LaCAM searches on for a plan that fits
    in the episode's steps."""
    if name == "lacam":
        return LaCAM(level_of(grid), goals, seed=0, max_nodes=nodes, horizon=STEPS)
    return PIBT(level_of(grid), goals, seed=0)


def episodes(mazes: list[dict], robots: tuple[int, ...], finished: str = "stay", planner: str | None = None,
             nodes: int = LACAM_NODES) -> dict[int, list[Episode]]:
    """The shortest-path crowd's episode on every maze, per robot count (``planner``: that planner's crowd)."""
    return {n: [race(m["grid"], cells(m["scenarios"][str(n)]["starts"]), cells(m["scenarios"][str(n)]["goals"]), finished,
                     planner, nodes) for m in mazes] for n in robots}


def run(mazes: list[dict], robots: tuple[int, ...], finished: str = "stay") -> dict[int, dict[str, float]]:
    """POGEMA's metrics with their intervals per robot count, over the given mazes."""
    return metrics(episodes(mazes, robots, finished))


def metrics(by_count: dict[int, list[Episode]]) -> dict[int, dict[str, float]]:
    return {n: crowd_metrics(eps, n, STEPS) for n, eps in by_count.items()}


def table(results: dict[int, dict[str, float]], n_mazes: int,
          others: dict[str, dict[int, dict[str, float]]] | None = None, finished: str = "stay") -> str:
    """Our metrics per robot count (value [low, high]), any other crowd's below (``others``: name ->
    results), then the published CSR with its source."""
    lines = [f"shortest-path robots on {n_mazes} of POGEMA's validation mazes, {STEPS} steps, soft collisions; "
             "95% intervals in brackets",
             f"{'':<34}{'robots':>6}  {'CSR (all_reached_rate)':<24}{'ISR (success_rate)':<24}{'sum of costs':<26}"
             "makespan"]
    here = "here (robots stay on their goals)" if finished == "stay" else "here (a robot leaves at its goal)"
    for name, res in {here: results, **(others or {})}.items():
        for n, m in res.items():
            cols = [_shown(m, k, 2 if k.endswith("rate") else 1) for k in ("all_reached_rate", "success_rate",
                                                                             "sum_of_costs", "makespan")]
            lines.append(f"{name:<34}{n:>6}  {cols[0]:<24}{cols[1]:<24}{cols[2]:<26}{cols[3]}")
            name = ""
    lines += ["", f"CSR at 32 / 64 robots ({SOURCE}):"]
    for name, (a, b) in PUBLISHED.items():
        lines.append(f"  {name:<28}{a:.2f} / {b:.2f}")
    ours = {"shortest-path robots (ours)": results}
    for name, res in (others or {}).items():
        ours.update({label: res for start, label in SUMMARY_LABELS.items() if name.startswith(start)})
    for name, res in ours.items():
        if any(n in res for n in (32, 64)):
            shown = " / ".join(_shown(res[n], "all_reached_rate", 2) if n in res else "-" for n in (32, 64))
            lines.append(f"  {name:<28}{shown}")
    return "\n".join(lines)


def _shown(m: dict[str, float], k: str, digits: int) -> str:
    return f"{m[k]:.{digits}f} [{m[k + '_low']:.{digits}f}, {m[k + '_high']:.{digits}f}]"


# The same crowd in POGEMA itself, run by its own interpreter: one JSON line of tasks in, one line per
# episode out (each robot's finishing step, 0: not within the episode, and the episode's steps).
WORKER = r"""
import collections, json, sys
from pogema import GridConfig, pogema_v0

sys.setrecursionlimit(100_000)  # the soft rule reverts chains of robots recursively
OURS = ((0, 0), (-1, 0), (0, 1), (1, 0), (0, -1))  # STAY, NORTH, EAST, SOUTH, WEST as (row, column) moves
TO_POGEMA = (0, 1, 4, 2, 3)


def distances(rows, goal):
    seen, todo = {goal: 0}, collections.deque([goal])
    while todo:
        r, c = todo.popleft()
        for dr, dc in OURS[1:]:
            n = (r + dr, c + dc)
            if 0 <= n[0] < len(rows) and 0 <= n[1] < len(rows[0]) and rows[n[0]][n[1]] == "." and n not in seen:
                seen[n] = seen[r, c] + 1
                todo.append(n)
    return seen


def action(dist, cell):  # the lowest of our action numbers on a shortest path; STAY on the goal
    for a in range(1, 5):
        n = (cell[0] + OURS[a][0], cell[1] + OURS[a][1])
        if dist.get(n, 10**9) == dist[cell] - 1:
            return TO_POGEMA[a]
    return 0


task = json.loads(sys.stdin.readline())
for grid, starts, goals in task["episodes"]:
    rows = grid.split("\n")
    config = GridConfig(map=grid, agents_xy=[(y, x) for x, y in starts], targets_xy=[(y, x) for x, y in goals],
                        on_target=task["on_target"], collision_system="soft", max_episode_steps=task["steps"],
                        observation_type="MAPF")
    env = pogema_v0(grid_config=config)
    env.reset()
    dists = [distances(rows, (y, x)) for x, y in goals]
    finish, t, done = [0] * len(starts), 0, False
    while not done:
        cells = env.grid.get_agents_xy(ignore_borders=True)
        _, _, terminated, truncated, _ = env.step([action(d, tuple(c)) for d, c in zip(dists, cells)])
        t += 1
        cells = env.grid.get_agents_xy(ignore_borders=True)
        for i, (c, g) in enumerate(zip(cells, goals)):
            there = not env.grid.is_active[i] or tuple(c) == (g[1], g[0])
            finish[i] = (finish[i] or t) if there else 0  # the last arrival (a robot may leave its goal again)
        done = all(terminated) or all(truncated)
    print(json.dumps([finish, t]), flush=True)
"""


def in_pogema(python: str, mazes: list[dict], robots: tuple[int, ...], on_target: str) -> dict[int, list[Episode]]:
    """The shortest-path crowd stepped by POGEMA 1.4 itself, per robot count."""
    tasks = [(m["grid"], cells(m["scenarios"][str(n)]["starts"]), cells(m["scenarios"][str(n)]["goals"]))
             for n in robots for m in mazes]
    done = subprocess.run([python, "-c", WORKER], input=json.dumps({"episodes": tasks, "on_target": on_target,
                                                                    "steps": STEPS}) + "\n",
                          capture_output=True, text=True, check=False)
    if done.returncode:
        raise SystemExit(f"--pogema-python: POGEMA's run failed: {done.stderr.strip().splitlines()[-1:]}")
    lines = [json.loads(line) for line in done.stdout.splitlines()]
    out: dict[int, list[Episode]] = {}
    for (grid, _, _), (finish, steps) in zip(tasks, lines):
        out.setdefault(len(finish), []).append(Episode(seed=0, level=grid, steps=steps, finish_steps=finish))
    return out


def regenerate(python: str) -> str:
    """The data file as POGEMA's venv writes it now (``pogema_mazes_data.py``)."""
    done = subprocess.run([python, str(MAKER)], capture_output=True, text=True, check=False)
    if done.returncode:
        raise SystemExit(f"--pogema-python: {MAKER.name} failed: {done.stderr.strip().splitlines()[-1:]}")
    return done.stdout


def load_crowd_policy(path: str) -> tuple[Any, str | None]:
    """The saved policy at ``path`` (a ``WindowPolicy`` of own goals), or ``None`` and the one line that says
    why it cannot run here (its file checked first)."""
    from babyrobot_marl.training.policy import load_checkpoint, load_policy

    try:
        data = load_checkpoint(path)
    except ValueError as err:
        return None, f"--policy: {str(err).removeprefix('policy: ')}"
    except ImportError as err:  # a policy file is read with torch (the train extra)
        return None, f"--policy: {err}"
    if data["observation"].get("goals", "exit") != "own":
        return None, (f"--policy: {path!r} was trained for the race to the exits; the benchmark needs a policy trained "
                      "with own goals: babyrobot-marl train --goals own --observe local --level maze:A..B ...")
    if data.get("env", {}).get("lifelong"):
        return None, f"--policy: {path!r} was trained lifelong; the benchmark's robots finish at their targets"
    return load_policy(path), None


def policy_race(policy: Any, grid: str, starts: list[tuple[int, int]], goals: list[tuple[int, int]],
                rng: np.random.Generator, greedy: bool, finished: str = "stay", shield: bool = False) -> Episode:
    """One episode of the learnt crowd: every robot reads its local window (target channel, hint) as
    ``race_v0`` shows it, the net runs once per distinct row (a recurrent net's cell once per robot, its state
    kept per robot); actions sampled (``greedy``: the likeliest).
    ``shield``: PIBT tries each robot's chosen action first, then its other moves nearest first, and keeps
    them from colliding."""
    import torch

    from babyrobot_marl.training.ppo.form import NO_ACTION
    from babyrobot_marl.training.ppo.intents import env_crowd
    from babyrobot_marl.training.ppo.net import actor_probs
    from babyrobot_marl.training.ppo.sampler import sample_actions
    from babyrobot_marl.training.ppo.trail import Trail
    from babyrobot_marl.training.ppo.turns import decide_in_turns

    form = policy.form
    env = race_v0.parallel_env(level=level_of(grid), n_robots=len(starts), goals="own", collisions="soft",
                               observe="local", view_radius=form.radius, hint=form.hint, start="random", max_cycles=STEPS,
                               finished=finished)
    obs, _ = env.reset(seed=0, options={"starts": starts, "goals": goals})
    names = {a: i for i, a in enumerate(env.possible_agents)}
    finish, last, t = [0] * len(starts), np.full(len(starts), NO_ACTION), 0
    planner = PIBT(level_of(grid), goals, seed=0) if shield else None
    net = policy.net
    memory = net.initial_state(len(starts)) if getattr(net, "recurrent", False) else None  # a GRU's state per robot
    trails = [Trail() for _ in starts] if form.trail else None  # where each robot has stood
    table = getattr(env.unwrapped, "race", env.unwrapped).table
    while env.agents:
        t += 1
        who = [names[a] for a in env.agents]
        seen = np.stack([obs[a] for a in env.agents])
        trail = None if trails is None else np.array([trails[i].peek(o[0], o[1], table) for i, o in zip(who, seen)])
        crowd = env_crowd(env, form) if form.intents else None  # what the robots near each one intend
        rows = form.rows_of_observations(seen, last[who], trail, None if crowd is None else crowd[0][who])
        uniq, inv = np.unique(rows, axis=0, return_inverse=True)
        with torch.no_grad():
            if form.turns:  # the robots choose in turns, each told what the near robots before it chose
                base = np.full((len(starts), rows.shape[1]), form.n_in, dtype=np.int64)
                base[who] = rows
                pick = (lambda q: q.argmax(axis=1)) if greedy else (lambda q: sample_actions(q, rng))  # noqa: E731
                chosen, p = decide_in_turns(base, *crowd[1:], lambda r: actor_probs(net, r), pick, form.turns_first, form.n_in)
                moves, p = np.maximum(chosen[0, who], 0), p[who]
            elif memory is None:
                p = actor_probs(net, uniq)[inv.reshape(-1)]
            else:  # the input part of the gates once per distinct row, the step per robot
                at = torch.tensor(who)
                memory[at] = net.step(net.gate_inputs(torch.from_numpy(uniq))[torch.from_numpy(inv.reshape(-1))], memory[at])
                p = torch.softmax(net.heads(memory[at])[0], 1).double().numpy()
        if not form.turns:
            sampled = sample_actions(p, rng)
            moves = p.argmax(axis=1) if greedy else sampled
        if planner is not None:  # robots that stay on their targets stay in the race: all of them are here
            chosen = np.zeros_like(p)
            chosen[np.arange(len(p)), moves] = 1.0
            moves = np.array(planner.actions(env.robot_cells, chosen))
        last[who] = moves
        for i in who if trails is not None else ():
            trails[i].mark()
        obs, _, _, _, infos = env.step(dict(zip(env.agents, moves.tolist())))
        arrivals(finish, infos, names, t)
    return Episode(seed=0, level=grid, steps=t, finish_steps=finish)


def policy_episodes(policy: Any, mazes: list[dict], robots: tuple[int, ...], seed: int,
                    greedy: bool, finished: str = "stay", shield: bool = False) -> dict[int, list[Episode]]:
    """The learnt crowd's episode on every maze, per robot count (one generator, seeded: same run, same figures)."""
    from babyrobot_marl.training.deps import torch_threads

    rng = np.random.default_rng(seed)
    with torch_threads(1):  # more threads stall on a busy machine, and a net this small gains nothing from them
        return {n: [policy_race(policy, m["grid"], cells(m["scenarios"][str(n)]["starts"]),
                                cells(m["scenarios"][str(n)]["goals"]), rng, greedy, finished, shield) for m in mazes]
                for n in robots}


def counts(text: str) -> tuple[int, ...]:
    allowed = (8, 16, 24, 32, 48, 64)
    try:
        values = tuple(int(v) for v in text.split(","))
    except ValueError:
        values = ()
    if not values or any(v not in allowed for v in values):
        raise argparse.ArgumentTypeError(f"robot counts from {', '.join(map(str, allowed))}, comma-separated; "
                                         f"got {text!r}")
    return values


def n_mazes(text: str) -> int:
    if not text.isdigit() or not 1 <= int(text) <= 128:
        raise argparse.ArgumentTypeError(f"an integer from 1 to 128, got {text!r}")
    return int(text)


def budget(text: str) -> int:
    if not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"a whole number of PIBT steps, at least 1; got {text!r}")
    return int(text)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--robots", type=counts, default=ROBOTS, help="robot counts (default: 8,16,32,48,64)")
    p.add_argument("--mazes", type=n_mazes, default=128, help="the first N of the 128 mazes (default: 128)")
    p.add_argument("--quick", action="store_true", help=f"CI smoke run: {QUICK_MAZES} mazes, 8 robots")
    p.add_argument("--policy", metavar="FILE",
                   help="also a policy saved by 'babyrobot-marl train --goals own --observe local' (its row below)")
    p.add_argument("--greedy", action="store_true", help="--policy: the likeliest action (default: sampled, --seed)")
    p.add_argument("--seed", type=int, default=0, help="--policy: the seed of its sampled actions (default: 0)")
    p.add_argument("--pibt", action="store_true",
                   help="also PIBT's crowd (a centralised planner, babyrobot_marl.planning.PIBT; robots that stay)")
    p.add_argument("--lacam", action="store_true",
                   help="also LaCAM's crowd (babyrobot_marl.planning.LaCAM: plans each episode before its first step)")
    p.add_argument("--lacam-nodes", type=budget, metavar="N",
                   help=f"--lacam: the PIBT steps its search may try per episode (default: {LACAM_NODES})")
    p.add_argument("--shield", action="store_true",
                   help="--policy: also the policy with PIBT as its collision shield (robots that stay)")
    p.add_argument("--finished", choices=tuple(ON_TARGET), default="stay",
                   help="a robot at its goal stays there, blocking (default, as the published runs), or leaves the board")
    p.add_argument("--json", action="store_true", help="end with one JSON line of the metrics")
    p.add_argument("--regenerate", action="store_true",
                   help="make the data again with POGEMA's venv (--pogema-python) and compare with the shipped file")
    p.add_argument("--in-pogema", action="store_true",
                   help="also step the same robots in POGEMA 1.4 itself (--pogema-python), with its on_target "
                   "'nothing' and 'finish' (the one matching --finished checked episode by episode)")
    p.add_argument("--pogema-python", default=os.environ.get("POGEMA_PYTHON"), metavar="PATH",
                   help="the python of a venv with pogema 1.4 (and pogema-toolbox 0.1.1 for --regenerate)")
    args = p.parse_args(argv)
    policy = None
    if args.policy is not None:
        policy, refused = load_crowd_policy(args.policy)
        if refused:
            p.exit(2, refused + "\n")
    if args.shield and args.policy is None:
        p.error("--shield: shields a learnt crowd; give its file with --policy FILE")
    if args.lacam_nodes is not None and not args.lacam:
        p.error("--lacam-nodes: the budget of LaCAM's search; add --lacam")
    planners = [flag for flag in ("pibt", "lacam", "shield") if getattr(args, flag)]
    if planners and args.finished != "stay":
        p.error(f"--{planners[0]}: {'LaCAM' if planners[0] == 'lacam' else 'PIBT'} plans robots that stay on their "
                "targets; use it with --finished stay")
    if (args.regenerate or args.in_pogema) and (not args.pogema_python or not Path(args.pogema_python).is_file()):
        p.error(f"--pogema-python: the python of a venv with pogema 1.4 (and pogema-toolbox for --regenerate), "
                f"got {args.pogema_python!r}")
    if args.regenerate:
        same = json.loads(regenerate(args.pogema_python)) == json.loads(DATA.read_text())
        print(f"{DATA.name}: {'the same as' if same else 'DIFFERENT from'} what POGEMA's venv makes now")
        if not same:
            return 1
    mazes, robots = load_mazes()[: QUICK_MAZES if args.quick else args.mazes], QUICK_ROBOTS if args.quick else args.robots
    ours = episodes(mazes, robots, args.finished)
    results, others = metrics(ours), {}
    if policy is not None:
        learnt = metrics(policy_episodes(policy, mazes, robots, args.seed, args.greedy, args.finished))
        how = "greedy" if args.greedy else "sampled"
        others[f"learnt policy ({how})"] = learnt
        if args.shield:
            others[f"shielded by PIBT ({how})"] = metrics(policy_episodes(policy, mazes, robots, args.seed, args.greedy,
                                                                          args.finished, shield=True))
    if args.pibt:
        others["PIBT (centralised planner)"] = metrics(episodes(mazes, robots, args.finished, "pibt"))
    if args.lacam:
        others["LaCAM (centralised planner)"] = metrics(episodes(mazes, robots, args.finished, "lacam",
                                                                 args.lacam_nodes or LACAM_NODES))
    if args.in_pogema:
        theirs = {rule: in_pogema(args.pogema_python, mazes, robots, rule) for rule in ("nothing", "finish")}
        matching = ON_TARGET[args.finished]
        same = all(a == b for n in robots for a, b in zip(ours[n], theirs[matching][n]))
        for rule, eps in theirs.items():
            others[f"POGEMA 1.4, on_target='{rule}'"] = metrics(eps)
        print(f"POGEMA 1.4 with on_target='{matching}': every episode {'the same as' if same else 'DIFFERENT from'} here")
    print(table(results, len(mazes), others, args.finished))
    if args.json:
        def kept(res: dict[int, dict[str, float]]) -> dict[str, dict[str, float]]:
            return {str(n): {k: m[k] for k in m if k.split("_low")[0].split("_high")[0] in METRICS} for n, m in res.items()}

        print(json.dumps({"shortest": kept(results), **({"policy": kept(learnt)} if policy is not None else {})}
                         if policy is not None else kept(results)))
    return 0 if not args.in_pogema or same else 1


if __name__ == "__main__":
    sys.exit(main())
