"""Regenerates models/furniture from the family code: `python -m ikea_suite.design.build`.

`--check` writes nothing and exits 1 when a committed model differs from what
the code makes (a stale models/ directory).
"""

import argparse
import pathlib
import sys

from ikea_suite.design import catalog
from ikea_suite.design import mjcf_writer
from ikea_suite.props import paths


def build_all(directory, check=False):
  """Writes (or, with check, compares) every model; returns the names that differ."""
  directory = pathlib.Path(directory)
  directory.mkdir(parents=True, exist_ok=True)
  stale = []
  wanted = set()
  for furniture in catalog.blueprints():
    text = mjcf_writer.blueprint_to_xml(furniture)
    path = directory / f"{furniture.name}.xml"
    wanted.add(path.name)
    if not path.is_file() or path.read_text() != text:
      stale.append(furniture.name)
      if not check:
        path.write_text(text)
  extra = sorted(p.name for p in directory.glob("*.xml") if p.name not in wanted)
  stale.extend(f"{name} (no family makes it)" for name in extra)
  if not check:
    for name in extra:
      (directory / name).unlink()
  return stale


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__)
  parser.add_argument("--out", default=str(paths.furniture_dir()), help="models directory")
  parser.add_argument("--check", action="store_true", help="fail if models/ is stale")
  args = parser.parse_args(argv)
  stale = build_all(args.out, check=args.check)
  if args.check and stale:
    print(f"models/ is stale; run python -m ikea_suite.design.build. Differing: {stale}")
    return 1
  print(f"{'checked' if args.check else 'wrote'} {len(catalog.blueprints())} models in {args.out}"
        + (f"; updated {stale}" if stale and not args.check else ""))
  return 0


if __name__ == "__main__":
  sys.exit(main())
