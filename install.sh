#!/bin/bash
# Install ProgSurf for the current user on Debian 12: apt packages, a venv for PyPI packages,
# and a link of this checkout into FreeCAD's user Mod folder. Idempotent: a second run only
# checks and changes nothing.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
APT_PACKAGES=(freecad-python3 xvfb xauth python3-pytest python3-pytest-timeout python3-hypothesis
              python3-matplotlib python3-venv python3-pip)
PYPI_PACKAGES=(c3d)

say() { printf 'install.sh: %s\n' "$*"; }

as_root() {
    if [ "$(id -u)" -eq 0 ]; then
        "$@"
    elif command -v sudo >/dev/null 2>&1; then
        sudo "$@"
    else
        say "need root for '$*' and sudo is not available; run this script as root" >&2
        exit 1
    fi
}

# 1. apt packages, only when one is missing (apt-get update is slow and needs the network).
missing=()
for pkg in "${APT_PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$pkg")
    fi
done
if [ "${#missing[@]}" -gt 0 ]; then
    say "installing apt packages: ${missing[*]}"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get update -q
    as_root env DEBIAN_FRONTEND=noninteractive \
        apt-get install -y -q --no-install-recommends "${missing[@]}"
else
    say "apt packages present"
fi

# 2. HOME must exist: FreeCAD writes its user config there.
if [ -z "${HOME:-}" ]; then
    HOME="$(getent passwd "$(id -un)" | cut -d: -f6)"
    export HOME
fi
mkdir -p "$HOME"

# 3. A venv on FreeCAD's Python (/usr/bin/python3) that still sees the system's numpy,
#    pytest and FreeCAD bindings, for PyPI-only packages.
VENV="$ROOT/.venv"
if [ ! -x "$VENV/bin/python" ] || ! "$VENV/bin/python" -c 'import sys' >/dev/null 2>&1; then
    say "creating $VENV"
    rm -rf "$VENV"
    /usr/bin/python3 -m venv --system-site-packages "$VENV"
fi
for pkg in "${PYPI_PACKAGES[@]}"; do
    if ! "$VENV/bin/python" -m pip show -q "$pkg" >/dev/null 2>&1; then
        say "pip installing $pkg into $VENV"
        "$VENV/bin/python" -m pip install -q --disable-pip-version-check "$pkg"
    fi
done
# The marker that lets FreeCAD's start-up (Init.py, ProgSurf/venv_site.py) put this venv and
# tests/ on sys.path: a developer install. An Addon Manager install has neither.
MARKER="$VENV/progsurf-developer-install"
if [ ! -f "$MARKER" ]; then
    printf '%s\n' "Written by install.sh: FreeCAD puts $VENV's site-packages and $ROOT/tests" \
        "on sys.path at start-up (see ProgSurf/venv_site.py). Delete this file to stop it." \
        > "$MARKER"
fi
say "venv ready: $VENV"

# 4. Link the checkout into FreeCAD's user Mod folder (0.20: ~/.local/share/FreeCAD/Mod).
MOD_DIR="$HOME/.local/share/FreeCAD/Mod"
LINK="$MOD_DIR/ProgSurf"
mkdir -p "$MOD_DIR"
if [ -L "$LINK" ]; then
    if [ "$(readlink -f "$LINK")" != "$ROOT" ]; then
        say "replacing stale link $LINK -> $(readlink "$LINK")"
        rm -f "$LINK"
    fi
elif [ -e "$LINK" ]; then
    # Outside Mod/, or FreeCAD would load the old copy as a second workbench.
    backup="$(dirname "$MOD_DIR")/ProgSurf.moved-aside.$(date +%Y%m%d%H%M%S)"
    say "$LINK is a real directory, not a link; moving it to $backup (nothing is deleted)"
    mv "$LINK" "$backup"
fi
if [ ! -e "$LINK" ]; then
    ln -s "$ROOT" "$LINK"
    say "linked $LINK -> $ROOT"
else
    say "FreeCAD Mod link present: $LINK -> $ROOT"
fi
