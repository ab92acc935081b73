"""Regenerates models/furniture from the family code: `python -m ikea_suite.design.build`.

Every model is written as one XML file plus the mesh files it uses under
meshes/ (named by content hash, so identical parts share a file). `--check`
writes nothing and exits 1 when a committed file differs from what the code
makes, or a file is left over that no family makes (a stale models/ directory).
"""

import argparse
import pathlib
import sys

import tqdm

from ikea_suite.design import family_models
from ikea_suite.design import mjcf_writer
from ikea_suite.props import paths


def generated_files(progress=False):
  """Relative path -> bytes of every file of every model, in name order."""
  files = {}
  blueprints = family_models.blueprints()
  for furniture in tqdm.tqdm(blueprints, desc="models", unit="model", disable=not progress):
    files.update(mjcf_writer.model_files(furniture))
  return files


def _existing(directory):
  return {p.relative_to(directory).as_posix() for pattern in ("*.xml", "meshes/*")
          for p in directory.glob(pattern) if p.is_file()}


def build_all(directory, check=False, progress=False):
  """Writes (or, with check, compares) every file; returns the relative paths that differ."""
  directory = pathlib.Path(directory)
  files = generated_files(progress)
  stale = [rel for rel, data in files.items()
           if not (directory / rel).is_file() or (directory / rel).read_bytes() != data]
  extra = sorted(_existing(directory) - set(files)) if directory.is_dir() else []
  if not check:
    for rel in stale:
      (directory / rel).parent.mkdir(parents=True, exist_ok=True)
      (directory / rel).write_bytes(files[rel])
    for rel in extra:
      (directory / rel).unlink()
  return sorted(stale) + [f"{rel} (no family makes it)" for rel in extra]


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__)
  parser.add_argument("--out", default=str(paths.furniture_dir()), help="models directory")
  parser.add_argument("--check", action="store_true", help="fail if models/ is stale")
  args = parser.parse_args(argv)
  stale = build_all(args.out, check=args.check, progress=sys.stderr.isatty() or not args.check)
  count = len(family_models.blueprints())
  if args.check:
    if stale:
      print(f"models/ is stale; run python -m ikea_suite.design.build. Differing files: {stale}")
      return 1
    print(f"checked {count} models in {args.out}: up to date")
    return 0
  print(f"wrote {count} models in {args.out}; {len(stale)} files changed")
  return 0


if __name__ == "__main__":
  sys.exit(main())
