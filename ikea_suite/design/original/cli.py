"""`ikea-suite-import-original`: converts models of the original IKEA environment to ours.

    ikea-suite-import-original ~/furniture/models/furniture --out ~/my_models
    ikea-suite-import-original chair_agne.xml table_lack.xml --out ~/my_models --material particleboard

Each SRC is an original-format XML file or a folder of them (with its subfolders,
unless --no-recursive; a file from a subfolder is written to the same subfolder
of --out and named by its path in the table). Every model is
converted (see ikea_suite.design.original.convert), checked by our
validation (ikea_suite.design.validate) and assembled by the Cursor oracle,
once per --seed; a table per model follows, then the repairs made and, for every
model that could not be converted, the reason. Exit status 0 when every
model converted, validated and was assembled, else 1; 2 for bad arguments.
Use the result with `ikea_suite.register_models(DIR)` or
`ikea_suite.load("DIR/NAME.xml")`.
"""

import argparse
import dataclasses
import pathlib
import sys

import tqdm

import ikea_suite  # sets MUJOCO_GL=egl on a display-less Linux machine
from ikea_suite import cli as rollout
from ikea_suite import errors
from ikea_suite.design import validate
from ikea_suite.design.original import convert
from ikea_suite.experts import cursor_oracle

SKIPPED = "skipped"
COLUMNS = ("model", "parts", "connectors", "mated pairs", "validation", "oracle")


@dataclasses.dataclass
class Row:
  """One model's line of the table, and what is printed under it."""
  source: str
  model: str = "-"
  parts: str = "-"
  connectors: str = "-"
  pairs: str = "-"
  validation: str = "-"
  oracle: str = "-"
  notes: list = dataclasses.field(default_factory=list)
  error: str = ""

  @property
  def ok(self):
    return (not self.error and self.validation == "ok"
            and (self.oracle.startswith("ok") or self.oracle == SKIPPED))

  def cells(self):
    return (self.model, self.parts, self.connectors, self.pairs, self.validation, self.oracle)


def sources(paths: list[str], recursive: bool = True) -> list[tuple[pathlib.Path, pathlib.Path]]:
  """The XML files named by `paths`, in order, each with the subfolder its output goes to.

  A folder stands for its *.xml files and, when `recursive`, those of every folder
  below it (the original's own `incomplete/` folder, a model's variant kept in its
  mesh folder). A file found in a subfolder is written to the same subfolder of
  the output, so files of the same name in different folders do not overwrite
  each other.

  Args:
    paths: files and folders as given on the command line.
    recursive: False reads only the *.xml files directly in each folder.

  Returns:
    (XML file, output subfolder relative to --out) pairs; each folder's files sorted by
    their path, a folder's own files before its subfolders'.

  Raises:
    ConversionError: a path that is neither an XML file nor a folder holding one.
  """
  files = []
  for path in map(pathlib.Path, paths):
    if path.is_dir():
      found = path.rglob("*.xml") if recursive else path.glob("*.xml")
      found = sorted((f for f in found if f.is_file()),
                     key=lambda f: (len(f.relative_to(path).parts), f.relative_to(path).parts))
      if not found:
        raise errors.ConversionError(path, "<folder>", "holds no *.xml model files")
      files += [(f, f.parent.relative_to(path)) for f in found]
    elif path.is_file():
      files.append((path, pathlib.Path()))
    else:
      raise errors.ConversionError(path, "<file>", "no such file or folder")
  return files


def oracle_result(path: pathlib.Path, seed: int) -> str:
  """One Cursor oracle episode on a model file.

  Args:
    path: the converted model file.
    seed: the episode's seed.

  Returns:
    'ok, N steps' when the oracle assembles it, else what went wrong.
  """
  try:
    env = ikea_suite.load(str(path), "cursor", seed=seed)
    summary = rollout.run_episode(env, cursor_oracle.CursorOracle(env))
  except (ikea_suite.IkeaSuiteError, ValueError) as e:   # sequencing: a stuck part is a ValueError
    return f"error: {e}"
  if summary["success"]:
    return f"ok, {summary['steps']} steps"
  return f"FAIL, {summary['connections']}/{summary['needed']} connections"


def oracle_results(path: pathlib.Path, seeds: list[int]) -> str:
  """Cursor oracle episodes on a model file, one per seed, summed up in one cell.

  Args:
    path: the converted model file.
    seeds: the episodes' seeds.

  Returns:
    oracle_result's text for one seed; for several, 'ok, K/K seeds, A-B steps' when every
    episode assembles it, else 'FAIL on J/K seeds' and each failing seed's result.
  """
  results = {seed: oracle_result(path, seed) for seed in seeds}
  if len(seeds) == 1:
    return results[seeds[0]]
  failed = {seed: r for seed, r in results.items() if not r.startswith("ok")}
  if not failed:
    steps = [int(r.split()[1]) for r in results.values()]
    return f"ok, {len(seeds)}/{len(seeds)} seeds, {min(steps)}-{max(steps)} steps"
  return (f"FAIL on {len(failed)}/{len(seeds)} seeds: "
          + "; ".join(f"seed {seed} {r}" for seed, r in failed.items()))


def process(source: pathlib.Path, out: str, material: str | None, category: str,
            seed: int | list[int], run_oracle: bool = True,
            subfolder: pathlib.Path = pathlib.Path()) -> Row:
  """Converts, validates and (optionally) assembles one model.

  Args:
    source: the original-format XML file.
    out: the output folder.
    material, category: as for convert.convert.
    seed: the oracle episode's seed, or a list of seeds (one episode each).
    run_oracle: False to skip the oracle.
    subfolder: where under `out` the model is written (and how its row names it).

  Returns:
    The model's Row: counts, validation and oracle results, repairs, or why it failed.
  """
  row = Row(str(source))
  label = (subfolder / source.stem).as_posix()
  try:
    result = convert.convert(source, pathlib.Path(out) / subfolder, material=material,
                             category=category)
  except errors.ConversionError as e:
    row.model, row.error = label, f"{e.element}: {e.problem}"
    row.validation = row.oracle = "not converted"
    return row
  row.model, row.parts = (subfolder / result.name).as_posix(), str(result.num_parts)
  row.connectors, row.pairs = str(result.num_connectors), str(len(result.pairs))
  row.notes = result.notes
  report = validate.check(result.path)
  row.validation = "ok" if report.ok else "FAIL: " + "; ".join(report.problems)
  seeds = [seed] if isinstance(seed, int) else list(seed)
  row.oracle = oracle_results(result.path, seeds) if run_oracle else SKIPPED
  return row


def table(rows: list[Row]) -> str:
  """The rows as an aligned text table with COLUMNS as its header."""
  cells = [COLUMNS] + [r.cells() for r in rows]
  widths = [max(len(c[i]) for c in cells) for i in range(len(COLUMNS))]
  lines = [" | ".join(c.ljust(w) if i == 0 or i > 3 else c.rjust(w)
                      for i, (c, w) in enumerate(zip(line, widths))).rstrip() for line in cells]
  lines.insert(1, "-+-".join("-" * w for w in widths))
  return "\n".join(lines)


def details(rows: list[Row]) -> str:
  """Repairs of each converted model and the reason for each one that was not converted."""
  lines = []
  for r in rows:
    if r.error:
      lines.append(f"{r.model}: NOT CONVERTED ({r.source}): {r.error}")
    elif r.notes:
      lines.append(f"{r.model}: {len(r.notes)} repairs and notes")
      lines += [f"  - {n}" for n in r.notes]
  return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
  parser = argparse.ArgumentParser(description=__doc__,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
  parser.add_argument("src", nargs="+", help="original-format XML files or folders of them")
  parser.add_argument("--out", required=True, help="folder for the converted models and meshes")
  parser.add_argument("--material", default=None, choices=convert.material_names(),
                      help="give every part this material's density (default: the original masses)")
  parser.add_argument("--category", default=convert.DEFAULT_CATEGORY,
                      help="catalog category written in each model's metadata")
  parser.add_argument("--seed", type=int, nargs="+", default=[0],
                      help="seeds of the oracle's episodes, one episode each (default: 0)")
  parser.add_argument("--no-oracle", action="store_true", help="skip the Cursor oracle check")
  parser.add_argument("--recursive", action=argparse.BooleanOptionalAction, default=True,
                      help="read the *.xml files of a folder's subfolders too, writing each "
                           "to the same subfolder of --out (default; --no-recursive: only "
                           "the folder's own files)")
  args = parser.parse_args(argv)
  try:
    files = sources(args.src, args.recursive)
  except ikea_suite.IkeaSuiteError as e:
    print(f"error: {e}", file=sys.stderr)
    return 2
  pathlib.Path(args.out).mkdir(parents=True, exist_ok=True)
  rows = []
  for source, subfolder in tqdm.tqdm(files, desc="converting", unit="model", file=sys.stderr):
    rows.append(process(source, args.out, args.material, args.category, args.seed,
                        run_oracle=not args.no_oracle, subfolder=subfolder))
  print(table(rows))
  if details(rows):
    print()
    print(details(rows))
  good = sum(r.ok for r in rows)
  print(f"\n{good}/{len(rows)} models converted, validated and assembled; output in {args.out}")
  return 0 if good == len(rows) else 1


if __name__ == "__main__":
  sys.exit(main())
