#!/usr/bin/env bash
# Install vvea-design and everything it needs on a fresh Debian/Ubuntu machine:
# the system libraries for off-screen rendering (apt, when available), then the
# Python package (pip, editable) into the active Python — make a virtual
# environment first:
#
#     python3 -m venv .venv && . .venv/bin/activate && bash scripts/install.sh
#
# Pass "test" to include the test tools (and Chromium for the report test).
set -euo pipefail
cd "$(dirname "$0")/.."

PYTHON="${PYTHON:-python3}"
APT_PACKAGES=(libgl1 libegl1 libegl-mesa0 libgl1-mesa-dri libx11-6 libxrender1)
# the gmsh wheel's libgmsh.so (the FE's meshes) links its GUI libraries even when run headless (readelf -d)
APT_PACKAGES+=(libglu1-mesa libxcursor1 libxfixes3 libxext6 libxft2 libfontconfig1 libxinerama1 libgomp1 zlib1g)
if [ "${1:-}" = "test" ]; then
  APT_PACKAGES+=(chromium fonts-dejavu-core)  # headless browser for the report.html test
fi

# Refuse clearly, before anything is installed, when pip may not install into this interpreter
# (PEP 668 "externally-managed-environment", e.g. Debian 12's /usr/bin/python3).
if ! "$PYTHON" -m pip --version >/dev/null 2>&1; then
  echo "install.sh: '$PYTHON -m pip' does not work. Make a virtual environment first:" >&2
  echo "    python3 -m venv .venv && . .venv/bin/activate && bash scripts/install.sh" >&2
  exit 1
fi
managed="$("$PYTHON" - <<'PY'
import sys, sysconfig, pathlib
inside_venv = sys.prefix != sys.base_prefix
marker = pathlib.Path(sysconfig.get_path("stdlib")) / "EXTERNALLY-MANAGED"
print("yes" if marker.exists() and not inside_venv else "no")
PY
)"
if [ "$managed" = "yes" ] && [ -z "${PIP_BREAK_SYSTEM_PACKAGES:-}" ]; then
  echo "install.sh: $("$PYTHON" -c 'import sys; print(sys.executable)') is managed by the system (PEP 668):" >&2
  echo "pip may not install into it. Make a virtual environment first:" >&2
  echo "    python3 -m venv .venv && . .venv/bin/activate && bash scripts/install.sh" >&2
  exit 1
fi

if command -v apt-get >/dev/null 2>&1; then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else SUDO="__none__"; fi
  fi
  if [ "$SUDO" = "__none__" ]; then
    echo "install.sh: not root and no sudo: skipping apt packages (${APT_PACKAGES[*]}); renders may fail" >&2
  else
    missing=()
    for p in "${APT_PACKAGES[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
    if [ ${#missing[@]} -gt 0 ]; then
      $SUDO apt-get update -qq
      DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
    fi
  fi
fi

extra=""
if [ "${1:-}" = "test" ]; then extra="[test]"; fi
"$PYTHON" -m pip install --quiet --disable-pip-version-check -e ".${extra}"
if [ "${1:-}" = "test" ]; then  # the bench simulators the tests and studies use (not part of the library)
  "$PYTHON" -m pip install --quiet --disable-pip-version-check -e benches
fi
