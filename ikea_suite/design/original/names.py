"""Connector site names of the original format, and names made safe for our files.

A site is a connector exactly when its name contains `conn_site`. The grammar
is `<groupA>-<groupB>,<angle>,<angle>,...,conn_site<tag>`: the site sits on a
part of connector group A and mates a site `B-A` on another part; the angles
(degrees) are the allowed twists about the site's up axis, none meaning any
twist; the tag only keeps names unique.
"""

import dataclasses
import math
import pathlib
import re

from ikea_suite import errors

CONN_MARK = "conn_site"
_UNSAFE = re.compile(r"[^A-Za-z0-9_\-]+")


@dataclasses.dataclass(frozen=True)
class SiteName:
  """The parts of one connector site name."""
  group: str          # group A: the group of the part the site is on
  mates: str          # group B: the group it mates with
  twists_deg: tuple   # allowed twists in degrees, sorted in [0, 360); () = any twist
  tag: str

  @property
  def type(self):
    """Our connector type: the site's own 'A-B'."""
    return f"{self.group}-{self.mates}"

  @property
  def mate_type(self):
    """The type of the sites it mates with: 'B-A'."""
    return f"{self.mates}-{self.group}"


def is_connector(name: str | None) -> bool:
  """True for a connector site name (it contains `conn_site`)."""
  return CONN_MARK in (name or "")


def parse(name: str, path: str | pathlib.Path) -> SiteName:
  """Splits a connector site name into groups, twists and tag.

  Args:
    name: the site name, e.g. 'leg-table,0,90,180,270,conn_site1'.
    path: the file it comes from, for error messages.

  Returns:
    A SiteName.

  Raises:
    ConversionError: the name does not follow the grammar (says which piece is wrong).
  """
  label = f"<site name={name!r}>"
  fields = [f.strip() for f in name.split(",")]
  if len(fields) < 2 or CONN_MARK not in fields[-1]:
    raise errors.ConversionError(
        path, label, "a connector name reads '<groupA>-<groupB>,<angles>...,conn_site<tag>'; "
        "the last comma-separated field must hold 'conn_site'")
  groups = fields[0].split("-")
  if len(groups) != 2 or not all(groups):
    raise errors.ConversionError(
        path, label, f"{fields[0]!r} must be two connector groups joined by one '-'")
  twists = set()
  for field in fields[1:-1]:
    if not field:   # 'a-b,,conn_site1': the original skips empty angle fields
      continue
    try:
      angle = float(field)
    except ValueError:
      raise errors.ConversionError(
          path, label, f"twist {field!r} is not an angle in degrees") from None
    if not math.isfinite(angle):
      raise errors.ConversionError(path, label, f"twist {field!r} is not finite")
    twists.add(round(angle % 360.0, 6) % 360.0)
  tag = fields[-1].split(CONN_MARK, 1)[1]
  return SiteName(groups[0], groups[1], tuple(sorted(twists)), tag)


def safe(name: str) -> str:
  """`name` with every run of characters other than letters, digits, '_' and '-' made '_'."""
  return _UNSAFE.sub("_", name).strip("_") or "unnamed"
