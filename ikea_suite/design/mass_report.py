"""Per-model masses of the catalog: `python -m ikea_suite.design.mass_report`.

Prints, for every model, its category, part count, total mass, the plausible
range for its size (mass_ranges) and the largest mass ratio between two parts
joined in the assembled pose, then per category the lightest and heaviest
model. docs/catalog.md holds the same table, written by scripts/make_docs.py and kept
current by a test. The welded-neighbour ratio is reported, not limited: a light leg on a
heavy top is real furniture, but ratios far above 10:1 make soft welds sag
(the heavier part drives the lighter one's constraint).
"""

import argparse
import sys

from ikea_suite.design import mass_ranges
from ikea_suite.props import catalog


def rows():
  """One dict per catalog model, in name order."""
  out = []
  for entry in catalog.entries().values():
    spec = catalog.spec(entry.name)
    low, high = mass_ranges.plausible(entry.category, spec.extents())
    ratio, heavy, light = mass_ranges.welded_mass_ratios(spec)[0]
    out.append(dict(name=entry.name, category=entry.category, parts=entry.num_parts,
                    mass=spec.mass, low=low, high=high, ratio=ratio, pair=f"{heavy} / {light}",
                    heaviest=max(p.mass for p in spec.parts)))
  return out


def largest_ratio(table):
  """The row with the largest welded-neighbour mass ratio."""
  return max(table, key=lambda r: r["ratio"])


def markdown(table):
  """The per-model table, the per-category table and the largest welded ratio, in markdown."""
  lines = ["| model | category | parts | mass (kg) | plausible (kg) | heaviest part (kg) "
           "| welded ratio | heavier / lighter |", "|---|---|---:|---:|---:|---:|---:|---|"]
  for r in table:
    mark = "" if r["low"] <= r["mass"] <= r["high"] else " (outside)"
    lines.append(f"| {r['name']} | {r['category']} | {r['parts']} | {r['mass']:.1f} | "
                 f"{r['low']:.1f}–{r['high']:.1f}{mark} | {r['heaviest']:.1f} | "
                 f"{r['ratio']:.1f} | {r['pair']} |")
  lines += ["", "## Per category", "", "| category | models | lightest (kg) | heaviest (kg) |",
            "|---|---:|---:|---:|"]
  for category, members in by_category(table).items():
    lo = min(members, key=lambda r: r["mass"])
    hi = max(members, key=lambda r: r["mass"])
    lines.append(f"| {category} | {len(members)} | {lo['mass']:.1f} ({lo['name']}) | "
                 f"{hi['mass']:.1f} ({hi['name']}) |")
  top = largest_ratio(table)
  lines += ["", f"Largest welded-neighbour mass ratio: {top['ratio']:.1f}:1 in {top['name']} "
            f"({top['pair']}).", ""]
  return "\n".join(lines)


def by_category(table):
  out = {}
  for r in table:
    out.setdefault(r["category"], []).append(r)
  return dict(sorted(out.items()))


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
  parser.parse_args(argv)
  print(markdown(rows()))
  return 0


if __name__ == "__main__":
  sys.exit(main())
