"""Paper section 6: optimal 50 N m torque step, variable vs fixed damping (Table 6, Fig. 14).

    python studies/safety.py            # -> studies/results/safety/
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from vvea_design.actuator.safety import run_safety


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "safety")
    a = ap.parse_args()
    s = run_safety(a.out).to_dict()
    print(json.dumps({k: s[k] for k in ("cases", "variable_start_won", "variable_D_settles_near_min_at_s")},
                     indent=1))


if __name__ == "__main__":
    main()
