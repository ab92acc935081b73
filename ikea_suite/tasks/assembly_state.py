"""Which parts are joined: union-find over parts, used connectors, the connection list."""

import numpy as np


class AssemblyState:
  """The scene graph of one episode; plain Python, reset at every episode start."""

  def __init__(self, num_parts, num_connectors):
    self._num_parts = num_parts
    self._num_connectors = num_connectors
    self.reset()

  def reset(self):
    self._parent = list(range(self._num_parts))
    self._num_groups = self._num_parts   # kept by connect: read twice every control step
    self.connector_used = np.zeros(self._num_connectors, dtype=bool)
    self.adjacency = np.zeros((self._num_parts, self._num_parts))
    self.connections = []   # (connector_a, connector_b) in the order they were made
    self.closures = []      # (connector_a, connector_b) welded because they came to coincide

  def group_of(self, part):
    root = part
    while self._parent[root] != root:
      root = self._parent[root]
    self._parent[part] = root
    return root

  def same_group(self, part_a, part_b):
    return self.group_of(part_a) == self.group_of(part_b)

  def group_members(self, part):
    root = self.group_of(part)
    return [p for p in range(self._num_parts) if self.group_of(p) == root]

  def group_labels(self):
    return np.array([self.group_of(p) for p in range(self._num_parts)])

  def connect(self, part_a, part_b, connector_a, connector_b):
    root_a, root_b = self.group_of(part_a), self.group_of(part_b)
    if root_a != root_b:
      self._parent[root_b] = root_a
      self._num_groups -= 1
    self.connector_used[[connector_a, connector_b]] = True
    self.adjacency[part_a, part_b] = self.adjacency[part_b, part_a] = 1.0
    self.connections.append((connector_a, connector_b))

  def close_loop(self, part_a, part_b, connector_a, connector_b):
    """Records a weld between two parts already in one group."""
    self.connector_used[[connector_a, connector_b]] = True
    self.adjacency[part_a, part_b] = self.adjacency[part_b, part_a] = 1.0
    self.closures.append((connector_a, connector_b))

  @property
  def num_groups(self):
    return self._num_groups

  @property
  def complete(self):
    return self.num_groups == 1
