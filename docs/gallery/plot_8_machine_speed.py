"""
The whole machine against speed
===============================

The STB loom of seed 000 (``examples/stb_loom.toml``): its lifter cam, the
rebound at the lifter's stop and the optimised cyclogram at every speed of a
sweep, with the speed limit and what sets it. ``cyclomech run
examples/stb_loom.toml`` writes the same, and much more, as an HTML report.
"""

from pathlib import Path

import cyclomech as cm
import matplotlib.pyplot as plt
from cyclomech.plot import plot_speed_sweep

# The examples folder of a clone: in the working directory or one above it (the
# documentation build runs this script from docs/gallery/).
here = Path.cwd().resolve()
loom = next(
    (
        d / "examples" / "stb_loom.toml"
        for d in (here, *here.parents)
        if (d / "examples" / "stb_loom.toml").exists()
    ),
    None,
)
if loom is None:
    raise SystemExit(
        "this script reads examples/stb_loom.toml of a cyclomech clone: run it from the "
        "clone (or a folder in it), or copy the file from the repository's examples/"
    )
m = cm.Machine.from_toml(loom)
limit = m.speed_limit()
print(f"speed limit: {limit.rpm:.2f} rpm, set by {limit.by}: {limit.reason}")
plot_speed_sweep(m.speed_sweep(), limit_rpm=limit.rpm)
plt.show()
