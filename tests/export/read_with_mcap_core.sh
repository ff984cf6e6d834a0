#!/usr/bin/env bash
# Reads an MCAP file with a reader that is not ours: Foxglove's @mcap/core (McapIndexedReader,
# which reads the summary, the chunk and message indexes and checks the CRCs), then decodes
# one message of each schema with protobufjs from the schema's own FileDescriptorSet.
#
#   bash tests/export/read_with_mcap_core.sh FILE.mcap
#
# The npm packages (pinned) are installed once into a cache outside the source tree
# ($OMNIVIEW_NPM_CACHE, else ~/.cache/omniview/npm) and never shipped. Without node or
# without the registry the check fails, saying so: it is never skipped silently.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
packages=(@mcap/core@2.2.2 protobufjs@7.6.6 fzstd@0.1.1)
cache="${OMNIVIEW_NPM_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/omniview/npm}/mcap-check-1"
command -v node > /dev/null && command -v npm > /dev/null ||
  { echo "read_with_mcap_core: node and npm are needed (scripts/install-deps.sh installs nodejs)" >&2; exit 1; }
mkdir -p "$cache"
(
  flock 9  # tests running side by side install once
  if [ ! -f "$cache/installed" ]; then
    if ! npm install --prefix "$cache" --no-audit --no-fund --no-save --loglevel=error "${packages[@]}" >&2; then
      echo "read_with_mcap_core: npm could not install ${packages[*]} into $cache (is the npm registry reachable?)" >&2
      exit 1
    fi
    touch "$cache/installed"
  fi
) 9> "$cache.lock"
NODE_PATH="$cache/node_modules" exec node "$here/read_with_mcap_core.cjs" "$@"
