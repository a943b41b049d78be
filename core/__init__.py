"""filmscale.core: the kernel every scale shares, and nothing else.

- errors: `FilmscaleError` and its kinds `InputError` (exit 2), `ModelRangeError` (exit 1),
  `EngineError` (exit 1);
- input checks: `check_real`, `check_positive`, `check_choice`, `check_keys`, ... (module
  `checks`), each naming the parameter, its value and the valid range;
- files: `atomic_path`, `atomic_h5`, `write_json`; the bounded readers `read_text`,
  `read_toml`, `read_json` (size limit, text only, nesting limit);
- `to_jsonable`: JSON without NaN or infinities; `provenance`: versions, platform, time;
- `noise_sigma`: the robust white-noise estimate of a sampled signal.

It imports no other part of filmscale.
"""

from .checks import check_choice, check_keys, check_positive, check_real
from .errors import EngineError, FilmscaleError, InputError, ModelRangeError
from .files import atomic_h5, atomic_path, read_json, read_text, write_json
from .jsonable import to_jsonable
from .noise import noise_sigma
from .provenance import provenance

__all__ = [
    "FilmscaleError", "InputError", "ModelRangeError", "EngineError",
    "check_real", "check_positive", "check_choice", "check_keys",
    "atomic_path", "atomic_h5", "write_json", "read_json", "read_text",
    "to_jsonable", "noise_sigma", "provenance",
]
