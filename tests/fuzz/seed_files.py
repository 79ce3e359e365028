"""What the seed makers of tests/fuzz (make_*_seeds.py) and the hostile-input maker share:
writing a target's seeds, and the SDK's constants read from their one declaration."""
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "bench"))
import sdk_constants  # noqa: E402 (the SDK's constants, read from their headers)


def standard_gravity():
    """m/s^2, as text: the SDK's one declaration (sdk/include/tern/math.hpp, kStandardGravity)."""
    return sdk_constants.literal("math.hpp", "kStandardGravity")


def write_seeds(out, seeds):
    """Writes each (file name -> bytes) of `seeds` into folder `out` (made if missing), saying its size."""
    os.makedirs(out, exist_ok=True)
    for name, data in seeds.items():
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)
        print(f"{name}: {len(data)} bytes")
