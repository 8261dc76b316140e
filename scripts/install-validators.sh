#!/usr/bin/env bash
# Installs the validators the export tests run (tests/tools/validators):
#   - the Khronos glTF validator (npm package gltf-validator, version pinned in package.json and
#     package-lock.json) into tests/tools/validators/node_modules;
#   - xmllint and the COLLADA 1.4.1 schema come from Debian packages (scripts/install-deps.sh:
#     libxml2-utils, opencollada-tools).
# Fast no-op when the pinned version is already installed.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dir="$here/tests/tools/validators"
want="$(node -e 'process.stdout.write(require(process.argv[1]).dependencies["gltf-validator"])' "$dir/package.json" 2>/dev/null || true)"
have="$(node -e 'process.stdout.write(require(process.argv[1]).version)' "$dir/node_modules/gltf-validator/package.json" 2>/dev/null || true)"
if [ -n "$want" ] && [ "$want" = "$have" ]; then
  exit 0
fi

if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  # Debian's own nodejs + npm (a machine whose nodejs already ships npm never gets here).
  echo "atmoglobe: node/npm missing: installing Debian nodejs npm" >&2
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends nodejs npm
fi
echo "atmoglobe: installing gltf-validator ${want:-?} into $dir/node_modules" >&2
cd "$dir"
# npm ci installs exactly what package-lock.json records.
npm ci --no-audit --no-fund --loglevel=error
