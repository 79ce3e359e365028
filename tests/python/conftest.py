"""tern's Python tests (ctest python_*): `import tern` from the build tree (PYTHONPATH=BUILD/python,
set by tests/CMakeLists.txt), flights in a temporary directory, plugins from BUILD/plugins."""
import os
from pathlib import Path

import pytest

# Under a sanitizer build the runtime is preloaded for this interpreter (tests/CMakeLists.txt); it
# is not for the programs the tests start: tern links it itself, and a preloaded ThreadSanitizer
# crashes an uninstrumented bash (tern new-plugin's script) at its start. A test that starts
# another Python which imports tern hands it SANITIZER_PRELOAD (python_env()).
SANITIZER_PRELOAD = os.environ.pop("LD_PRELOAD", None)


def python_env(**extra):
    """The environment of a child python3 that imports tern: this one's, with the sanitizer's
    preload back (in a sanitizer build) and `extra`."""
    env = {**os.environ, **extra}
    if SANITIZER_PRELOAD:
        env["LD_PRELOAD"] = SANITIZER_PRELOAD
    return env

SOURCE = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("TERN_BUILD_DIR", SOURCE / "build"))
LEARN = SOURCE / "configs" / "missions" / "learn.yaml"
DEFAULT = SOURCE / "configs" / "missions" / "default.yaml"


@pytest.fixture
def logs(tmp_path):
    return tmp_path / "runs"
