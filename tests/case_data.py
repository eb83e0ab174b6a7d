"""Edits of parsed case-file data for the input-check tests."""

import copy


def mutated(data: dict, path: list, value) -> dict:
    """A deep copy of ``data`` with ``path`` set to ``value`` (deleted if ``value`` is None)."""
    data = copy.deepcopy(data)
    node = data
    for key in path[:-1]:
        node = node[key]
    if value is None:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return data
