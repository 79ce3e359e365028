"""tern's Python tests (ctest python_*): `import tern` from the build tree (PYTHONPATH=BUILD/python,
set by tests/CMakeLists.txt), flights in a temporary directory, plugins from BUILD/plugins."""
import os
from pathlib import Path

import pytest

# Under a sanitizer build the runtime is preloaded for this interpreter (tests/CMakeLists.txt); it
# is not for the programs the tests start: tern links it itself, and a preloaded ThreadSanitizer
# crashes an uninstrumented bash (tern new-plugin's script) at its start.
os.environ.pop("LD_PRELOAD", None)

SOURCE = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("TERN_BUILD_DIR", SOURCE / "build"))
LEARN = SOURCE / "configs" / "missions" / "learn.yaml"
DEFAULT = SOURCE / "configs" / "missions" / "default.yaml"


@pytest.fixture
def logs(tmp_path):
    return tmp_path / "runs"
