"""Job specs built in Python: a base spec with fields set by their dotted paths.

The paths are the job spec's own (docs/job-spec.md), the ones a study varies
(docs/studies.md): ``with_fields(base, {"specimen.wire.pattern": "helix",
"seed": 2})``. The server validates the result (unknown keys are errors), so
nothing is checked here.
"""
from __future__ import annotations

import copy
import json
import os
from pathlib import Path
from typing import Any, Dict, Mapping, Union


def with_fields(base: Union[Mapping[str, Any], str, "os.PathLike[str]", None] = None,
                fields: Mapping[str, Any] = {}, **top_level: Any) -> Dict[str, Any]:
    """A copy of ``base`` (a dict, the path of a JSON file, or None for ``{}``: every default)
    with each dotted path of ``fields`` set, and each keyword as a top-level field.

    >>> with_fields({"name": "a"}, {"triaxial.confining_pressures_pa": [20000]}, seed=3)
    {'name': 'a', 'triaxial': {'confining_pressures_pa': [20000]}, 'seed': 3}
    """
    if base is None:
        spec: Dict[str, Any] = {}
    elif isinstance(base, Mapping):
        spec = copy.deepcopy(dict(base))
    else:
        spec = json.loads(Path(os.fspath(base)).read_text())
    for path, value in list(fields.items()) + list(top_level.items()):
        keys = path.split(".")
        node = spec
        for k in keys[:-1]:
            child = node.get(k)
            if not isinstance(child, dict):
                child = node[k] = {}
            node = child
        node[keys[-1]] = copy.deepcopy(value)
    return spec
