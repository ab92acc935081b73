"""The progress bar of the dataset commands (collect, replay): tqdm on stderr, whose last
(100%) line is printed once.

tqdm draws the bar when the last item arrives and again when it closes; a terminal
overwrites the first with the second, but a log file or a notebook keeps both. Here the
last item only sets the count, and closing draws the 100% line.
"""

from collections.abc import Iterable, Iterator
from typing import TypeVar

import tqdm

Item = TypeVar("Item")


def progress(items: Iterable[Item], total: int, desc: str, unit: str,
             enabled: bool = True) -> Iterator[Item]:
  """Yields `items`, counting them on a progress bar on stderr.

  Args:
    items: what to count, `total` of them.
    total: how many items there are.
    desc: the bar's label ("collect").
    unit: what an item is ("episode").
    enabled: False draws nothing.
  Yields:
    The items, as they come.
  """
  with tqdm.tqdm(total=total, desc=desc, unit=unit, disable=not enabled) as bar:
    for count, item in enumerate(items, 1):
      if count < total:
        bar.update(1)
      else:
        bar.n = count   # close() draws the 100% line
      yield item
