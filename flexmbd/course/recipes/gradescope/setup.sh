#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder's image.
# It installs bubblewrap (the sandbox each submission runs in) and flexmbd, from the
# wheel beside this file when there is one, else from the package index.
set -euo pipefail
apt-get update
apt-get install -y --no-install-recommends bubblewrap python3 python3-venv python3-pip
python3 -m venv /opt/flexmbd
here="$(cd "$(dirname "$0")" && pwd)"
wheel="$(ls "$here"/flexmbd-*.whl 2>/dev/null | head -n 1 || true)"
/opt/flexmbd/bin/pip install --quiet "${wheel:-flexmbd==@VERSION@}"
