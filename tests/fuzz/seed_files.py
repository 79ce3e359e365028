"""What the seed makers of tests/fuzz (make_*_seeds.py) and the hostile-input maker share:
writing a target's seeds, and the SDK's constants read from their one declaration."""
import os
import re

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def standard_gravity():
    """m/s^2, as text: the SDK's one declaration (sdk/include/tern/math.hpp, kStandardGravity)."""
    with open(os.path.join(REPO, "sdk", "include", "tern", "math.hpp")) as f:
        return re.search(r"kStandardGravity = ([0-9.]+);", f.read()).group(1)


def write_seeds(out, seeds):
    """Writes each (file name -> bytes) of `seeds` into folder `out` (made if missing), saying its size."""
    os.makedirs(out, exist_ok=True)
    for name, data in seeds.items():
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)
        print(f"{name}: {len(data)} bytes")
