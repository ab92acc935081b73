"""The one registry of scripted experts: which expert drives each robot, in which control
modes, and which furniture it assembles at what scale.

The furniture lists are measurements, kept in supported.json beside this module and
written by `benchmarks/expert_sweep.py --write`: per robot and furniture, the scale the
sweep ran at, how many of its episodes completed the furniture, and on which seeds
(seeds the experts were never tuned on). A pair is supported when at least
SUPPORT_FRACTION of its episodes completed; a two-arm robot's pair also needs both arms
in at least SUPPORT_FRACTION of its complete episodes. Pairs measured below that stay
in the file, so the docs can name what fails. The Cursor oracle plans any model's
assembly sequence, so it is listed for the whole catalog at full size instead.
"""

import dataclasses
import functools
import json
import pathlib
from typing import Any, Iterable, Mapping, Sequence

from ikea_suite import environment
from ikea_suite import errors
from ikea_suite.experts import bimanual
from ikea_suite.experts import cursor_oracle
from ikea_suite.experts import single_arm
from ikea_suite.props import catalog

# Fraction of a pair's measured episodes that must complete the furniture to list it.
SUPPORT_FRACTION = 0.8
DATA_PATH = pathlib.Path(__file__).with_name("supported.json")


@dataclasses.dataclass(frozen=True)
class Expert:
  """One robot's scripted expert.

  Attributes:
    robot: the robot's name (ikea_suite.robot_names()).
    kind: the expert's name in datasets: "cursor_oracle", "single_arm" or "two_arm".
    policy: the expert's class, built with the environment; its CONTROL_MODES are the
      robot's control modes it drives (None for a robot without them, the Cursor), and
      building it in another mode raises.
    every_model: True when the expert assembles every catalog model at full size rather
      than a measured list.
  """
  robot: str
  kind: str
  policy: type
  every_model: bool = False

  @property
  def control_modes(self) -> tuple[str, ...] | None:
    """The robot's control modes the expert drives it in; None for a robot without them."""
    return self.policy.CONTROL_MODES

  @property
  def two_arm(self) -> bool:
    """Whether the expert works with two arms, each of which a supported pair must use."""
    return self.kind == "two_arm"


EXPERTS = {e.robot: e for e in (
    Expert("cursor", "cursor_oracle", cursor_oracle.CursorOracle, every_model=True),
    Expert("sawyer", "single_arm", single_arm.ArmAssemblyController),
    Expert("panda", "single_arm", single_arm.ArmAssemblyController),
    Expert("baxter", "two_arm", bimanual.TwoArmExpert),
    Expert("jaco", "single_arm", single_arm.ArmAssemblyController),
)}
ROBOTS = tuple(EXPERTS)


@dataclasses.dataclass(frozen=True)
class Measurement:
  """What a sweep measured of one robot's expert on one furniture model.

  Attributes:
    robot: the robot's name.
    furniture: the furniture's name.
    scale: the load(scale=...) factor the episodes ran at.
    completed: episodes that completed the furniture; None where no count is recorded
      (the Cursor's catalog-wide listing).
    episodes: episodes measured; None where no count is recorded.
    seeds: the seeds measured, as ranges ("37000-37009"); None where none are recorded.
    both_arms: complete episodes that used both arms (two-arm experts only, else None).
    supported: whether the pair meets the listing rule (module docstring).
  """
  robot: str
  furniture: str
  scale: float
  completed: int | None
  episodes: int | None
  seeds: str | None
  both_arms: int | None = None
  supported: bool = False


def expert(robot: str) -> Expert:
  """The registry entry of `robot`'s expert.

  Args:
    robot: a robot name.
  Returns:
    Its Expert entry.
  Raises:
    UnknownNameError: a robot with no expert.
  """
  if robot not in EXPERTS:
    raise errors.UnknownNameError("robot with an expert", robot, ROBOTS)
  return EXPERTS[robot]


def meets_rule(entry: Expert, completed: int, episodes: int, both_arms: int | None) -> bool:
  """The listing rule: SUPPORT_FRACTION of the episodes complete, and for a two-arm
  expert SUPPORT_FRACTION of the complete ones with both arms."""
  if episodes <= 0 or completed < SUPPORT_FRACTION * episodes:
    return False
  return not entry.two_arm or (both_arms or 0) >= SUPPORT_FRACTION * completed


def _load(path: pathlib.Path) -> dict[str, Any]:
  with open(path, encoding="utf-8") as f:
    return json.load(f)


@functools.lru_cache(maxsize=None)
def _table() -> dict[str, dict[str, Measurement]]:
  """robot -> furniture -> Measurement, read from DATA_PATH once."""
  data = _load(DATA_PATH)["robots"]
  table = {}
  for robot, entry in EXPERTS.items():
    rows = data.get(robot, {}).get("furniture", {})
    table[robot] = {}
    for furniture, row in rows.items():
      both = row.get("both_arms")
      table[robot][furniture] = Measurement(
          robot, furniture, float(row["scale"]), int(row["completed"]), int(row["episodes"]),
          row["seeds"], both, meets_rule(entry, row["completed"], row["episodes"], both))
  return table


def supported(robot: str) -> tuple[str, ...]:
  """Furniture names `robot`'s expert assembles (measured; see the module docstring).

  Args:
    robot: a robot name.
  Returns:
    Sorted furniture names (the Cursor: every catalog model).
  Raises:
    UnknownNameError: a robot with no expert.
  """
  if expert(robot).every_model:
    return tuple(catalog.names())
  return tuple(sorted(f for f, m in _table()[robot].items() if m.supported))


def measurement(robot: str, furniture: str) -> Measurement:
  """What the sweep measured of `robot`'s expert on `furniture`, listed or not.

  Args:
    robot: a robot name with an expert (ROBOTS).
    furniture: a furniture name measured for it (measurements(robot)); for the Cursor,
      any catalog model (scale 1.0, no counts recorded).
  Returns:
    The pair's Measurement.
  Raises:
    UnknownNameError: a robot with no expert, or a pair never measured.
  """
  if expert(robot).every_model:
    if furniture not in catalog.names():
      raise errors.UnknownNameError("furniture", furniture, catalog.names())
    return Measurement(robot, furniture, 1.0, None, None, None, None, True)
  table = _table()[robot]
  if furniture not in table:
    raise errors.UnknownNameError(f"furniture measured for the {robot} expert", furniture,
                                  table)
  return table[furniture]


def measurements(robot: str) -> tuple[Measurement, ...]:
  """Every recorded measurement of `robot`'s expert, listed or not, by furniture name.

  Args:
    robot: a robot name with an expert (ROBOTS).
  Returns:
    Measurements sorted by furniture (none for the Cursor, listed by design).
  Raises:
    UnknownNameError: a robot with no expert.
  """
  expert(robot)
  table = _table()[robot]
  return tuple(table[f] for f in sorted(table))


def supported_scale(robot: str, furniture: str) -> float:
  """The scale `robot`'s expert assembles `furniture` at (1.0 for the Cursor).

  Args:
    robot: a robot name with an expert (ROBOTS).
    furniture: a furniture name in supported(robot).
  Returns:
    The load(scale=...) factor the expert's measurement used.
  Raises:
    UnknownNameError: the pair is not supported.
  """
  if furniture not in supported(robot):
    raise errors.UnknownNameError(f"furniture the {robot} expert assembles", furniture,
                                  supported(robot))
  return measurement(robot, furniture).scale


def supported_pairs() -> tuple[tuple[str, str], ...]:
  """Every (furniture, robot) pair with an expert that assembles it.

  Returns:
    (furniture, robot) pairs, robot-major in ROBOTS order.
  """
  return tuple((f, r) for r in ROBOTS for f in supported(r))


def make_expert(env: environment.Environment, require_supported: bool = True) -> Any:
  """The scripted expert for `env`'s robot: a callable TimeStep -> action with reset().

  Args:
    env: an ikea_suite environment (arms in one of their expert's control_modes:
      "task_space" or "impedance").
    require_supported: refuse a furniture outside supported(robot), or one built at
      another scale than the expert was measured at (there it runs, but rarely completes
      the furniture, and says nothing); False runs the expert anyway (sweeps, experiments
      on new models).
  Returns:
    A policy object with reset(), __call__(timestep) and subtask.
  Raises:
    UnknownNameError: a robot with no expert.
    UnsupportedPairError: (require_supported) a furniture or scale the expert is not
      measured to assemble; the message names the furniture it assembles.
    IkeaSuiteError: an arm in a control mode its expert does not drive.
  """
  entry = expert(env.task.robot.mjcf_model.model)
  if require_supported:
    check_supported(entry.robot, env.task.furniture.name, env.task.furniture.scale)
  return entry.policy(env)


def check_supported(robot: str, furniture: str, scale: float) -> None:
  """Refuses a (furniture, scale) that `robot`'s expert is not measured to assemble.

  Args:
    robot: a robot name with an expert (ROBOTS).
    furniture: a furniture name.
    scale: the scale the furniture is built at (load(scale=...)).
  Raises:
    UnknownNameError: a robot with no expert.
    UnsupportedPairError: a furniture outside supported(robot), or a scale other than
      its measurement's (an expert listed for every model takes any scale).
  """
  names = supported(robot)
  anyway = "make_expert(env, require_supported=False) runs it anyway"
  if furniture not in names:
    raise errors.UnsupportedPairError(
        f"the {robot} expert is not measured to assemble {furniture!r}; it assembles "
        f"{len(names)} furniture models: {', '.join(names)} (experts.supported({robot!r})); "
        f"{anyway}")
  measured = measurement(robot, furniture).scale
  if not expert(robot).every_model and abs(scale - measured) > 1e-9:
    raise errors.UnsupportedPairError(
        f"the {robot} expert assembles {furniture!r} at scale {measured:g}, not {scale:g}; "
        f"load it with scale={measured:g}, or {anyway}")


def summarize(robot: str, furniture: str, episodes: Sequence[Mapping[str, Any]]) -> Measurement:
  """The Measurement of a sweep's episodes of one pair.

  Args:
    robot: a robot name with an expert (ROBOTS).
    furniture: the furniture's name.
    episodes: benchmarks/expert_sweep.py's episode summaries of the pair (each with
      "scale", "seed", "complete" and "arms_used"), all at one scale.
  Returns:
    The pair's Measurement, `supported` by the listing rule.
  Raises:
    IkeaSuiteError: no episodes, or episodes at more than one scale.
  """
  entry = expert(robot)
  scales = {float(e["scale"]) for e in episodes}
  if len(scales) != 1:
    raise errors.IkeaSuiteError(f"{robot} {furniture}: episodes at scales {sorted(scales)}; "
                                "a measurement needs one scale")
  completed = sum(bool(e["complete"]) for e in episodes)
  both = (sum(bool(e["complete"]) and len(e["arms_used"]) == 2 for e in episodes)
          if entry.two_arm else None)
  return Measurement(robot, furniture, scales.pop(), completed, len(episodes),
                     seed_ranges(e["seed"] for e in episodes), both,
                     meets_rule(entry, completed, len(episodes), both))


def seed_ranges(seeds: Iterable[int]) -> str:
  """Seeds written as comma-separated inclusive ranges: 37000-37009, 38000."""
  ordered = sorted(set(int(s) for s in seeds))
  ranges = []
  for seed in ordered:
    if ranges and seed == ranges[-1][1] + 1:
      ranges[-1][1] = seed
    else:
      ranges.append([seed, seed])
  return ", ".join(f"{a}-{b}" if b > a else f"{a}" for a, b in ranges)


def _row(m: Measurement) -> dict[str, Any]:
  row = {"scale": m.scale, "completed": m.completed, "episodes": m.episodes, "seeds": m.seeds}
  if m.both_arms is not None:
    row["both_arms"] = m.both_arms
  return row


def dumps(data: Mapping[str, Any]) -> str:
  """supported.json's text for `data`: one line per furniture, furniture sorted."""
  lines = ["{", f'  "about": {json.dumps(data["about"])},', '  "robots": {']
  robots = list(data["robots"].items())
  for k, (robot, entry) in enumerate(robots):
    lines.append(f"    {json.dumps(robot)}: {{")
    lines.append(f'      "notes": {json.dumps(entry.get("notes", []))},')
    lines.append('      "furniture": {')
    rows = sorted(entry.get("furniture", {}).items())
    for j, (furniture, row) in enumerate(rows):
      comma = "," if j < len(rows) - 1 else ""
      lines.append(f"        {json.dumps(furniture)}: {json.dumps(row)}{comma}")
    lines.append("      }")
    lines.append("    }" + ("," if k < len(robots) - 1 else ""))
  lines += ["  }", "}", ""]
  return "\n".join(lines)


def write(new: Iterable[Measurement], path: pathlib.Path | str | None = None) -> None:
  """Records sweep measurements in supported.json, replacing those of the same pairs.

  Args:
    new: measurements (summarize()); pairs not among them keep their records.
    path: the file to update (default: the package's own supported.json).
  Raises:
    IkeaSuiteError: a measurement of an expert listed for every model (the Cursor).
  """
  path = pathlib.Path(DATA_PATH if path is None else path)
  data = _load(path)
  for m in new:
    if expert(m.robot).every_model:
      raise errors.IkeaSuiteError(
          f"the {m.robot} expert is listed for every catalog model; its sweeps are not recorded")
    data["robots"].setdefault(m.robot, {"notes": [], "furniture": {}})
    data["robots"][m.robot].setdefault("furniture", {})[m.furniture] = _row(m)
  path.write_text(dumps(data), encoding="utf-8")
  _table.cache_clear()
