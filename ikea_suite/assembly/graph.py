"""Connected components of an assembly graph (parts as nodes, joined pairs as edges)."""


def components(nodes, edges):
  """Sorted lists of the nodes in each connected component; edges between nodes outside
  `nodes` are ignored. `nodes` is an iterable of ints (or a count, meaning range(count))."""
  nodes = list(range(nodes)) if isinstance(nodes, int) else sorted(nodes)
  parent = {n: n for n in nodes}

  def find(n):
    while parent[n] != n:
      parent[n] = parent[parent[n]]
      n = parent[n]
    return n
  for a, b in edges:
    if a in parent and b in parent:
      parent[find(a)] = find(b)
  groups = {}
  for n in nodes:
    groups.setdefault(find(n), []).append(n)
  return sorted(groups.values())


def connected(nodes, edges):
  """Whether `nodes` form one connected group through `edges` (an empty set counts as one)."""
  return len(components(nodes, edges)) <= 1
