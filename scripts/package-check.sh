#!/usr/bin/env bash
# Builds parity's Debian packages and installs them as a user would, then runs parity from the
# installed package. For a brand-new Debian 12 root (as root):
#   ../shared/tools/fresh-machine.sh . 'bash scripts/package-check.sh'
# Packages: build/parity_VERSION_ARCH.deb and build/parity-dev_VERSION_ARCH.deb.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh parity
(cd build && cpack -G DEB)
export DEBIAN_FRONTEND=noninteractive
apt-get install -y -qq ./build/parity_*.deb >/dev/null
work=$(mktemp -d)
cd "$work"
command -v parity
parity list
parity run --technique forward --require-backends gl,vk --out run --no-progress
