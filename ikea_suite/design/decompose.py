"""Convex decomposition of concave part meshes with coacd, cached by content hash.

MuJoCo collides the convex hull of a mesh, so a concave part (a frame, a
curved back, a bracket) collides through the convex pieces coacd finds. coacd
is slow and its output may vary across machines, so each result is stored
under the hash of the input mesh and the parameters: a rebuild reads the
cache and is fast and deterministic. The cache is committed with the models.
"""

import hashlib
import json
import os
import pathlib

import numpy as np
import trimesh

CACHE_ENV = "IKEA_SUITE_COACD_CACHE"
DEFAULT_CACHE = pathlib.Path(__file__).parent / "coacd_cache"
PARAMS = {"threshold": 0.05, "max_convex_hull": 8, "preprocess_mode": "off", "seed": 0}
_DIGITS = 7   # vertex rounding, so equal meshes hash equally across platforms


def cache_dir():
  """$IKEA_SUITE_COACD_CACHE, else the committed cache in a source checkout, else (an
  installed, read-only package) ~/.cache/ikea_suite/coacd."""
  if os.environ.get(CACHE_ENV):
    return pathlib.Path(os.environ[CACHE_ENV])
  if DEFAULT_CACHE.is_dir() and os.access(DEFAULT_CACHE, os.W_OK):
    return DEFAULT_CACHE
  return pathlib.Path.home() / ".cache" / "ikea_suite" / "coacd"


def content_key(mesh, params=None):
  """Hex digest of the mesh geometry and the decomposition parameters."""
  digest = hashlib.sha256()
  digest.update(np.round(np.asarray(mesh.vertices), _DIGITS).astype("<f8").tobytes())
  digest.update(np.asarray(mesh.faces).astype("<i8").tobytes())
  digest.update(json.dumps(params or PARAMS, sort_keys=True).encode())
  return digest.hexdigest()


def convex_pieces(mesh, directory=None, params=None):
  """Convex trimesh pieces whose union approximates `mesh`; a convex mesh is its own piece."""
  params = dict(params or PARAMS)
  if mesh.is_convex:
    return [mesh.convex_hull]
  directory = pathlib.Path(directory) if directory else cache_dir()
  path = directory / f"{content_key(mesh, params)[:24]}.json"
  if path.is_file():
    stored = json.loads(path.read_text())
    return [trimesh.Trimesh(p["vertices"], p["faces"]) for p in stored["pieces"]]
  pieces = [_hull(vertices) for vertices, _ in _run_coacd(mesh, params)]
  # Sorted so the written order never depends on coacd's internal order.
  pieces.sort(key=lambda p: tuple(np.round(p.bounds.ravel(), 4)))
  directory.mkdir(parents=True, exist_ok=True)
  stored = {"params": params, "pieces": [
      {"vertices": np.round(p.vertices, _DIGITS).tolist(), "faces": p.faces.tolist()}
      for p in pieces]}
  path.write_text(json.dumps(stored, separators=(",", ":")) + "\n")
  return pieces


def _hull(vertices):
  return trimesh.convex.convex_hull(np.round(np.asarray(vertices), _DIGITS))


def _run_coacd(mesh, params):
  import coacd   # imported late: only a cache miss needs it
  coacd.set_log_level("error")
  return coacd.run_coacd(coacd.Mesh(np.asarray(mesh.vertices), np.asarray(mesh.faces)), **params)
