#!/bin/sh
# `make docker-check`: builds docker/Dockerfile for real on a machine without a Docker engine or registry
# (../shared/docs/DOCKER.md) and checks the image: a Debian bookworm base made by debootstrap from the mirror
# apt already uses, buildah to build both stages (the build stage runs every test), then the runtime image's
# granulabd started on loopback, asked for its health and made to run the two-cube example to `succeeded`.
# Root only (debootstrap, buildah). Everything lives in a scratch folder, removed at the end (KEEP=1 keeps
# it, with the base and the build cache, for the next run). Run it whenever docker/ or the dependencies change.
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SCRATCH=${SCRATCH:-/var/tmp/granulab-docker-check}
[ "$(id -u)" = 0 ] || { echo "docker-check: needs root (debootstrap, buildah)" >&2; exit 1; }

step() { printf '\n== %s (%s)\n' "$1" "$(date +%T)"; }
cleanup() {
  [ -n "${DAEMON:-}" ] && kill "$DAEMON" 2>/dev/null && wait "$DAEMON" 2>/dev/null || true
  [ -n "${CTR:-}" ] && buildah rm "$CTR" >/dev/null 2>&1 || true
  if [ "${KEEP:-0}" != 1 ]; then
    buildah rmi --all --force >/dev/null 2>&1 || true
    rm -rf "$SCRATCH"
  fi
}
trap cleanup EXIT INT TERM

step "tools"
missing=""
for p in debootstrap buildah podman; do dpkg-query -W -f='${Status}' $p 2>/dev/null | grep -q "ok installed" || missing="$missing $p"; done
if [ -n "$missing" ]; then
  apt-get -o DPkg::Lock::Timeout=600 update
  DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=600 install -y --no-install-recommends $missing
fi

# Container storage in the scratch folder, not in the machine's default places.
mkdir -p "$SCRATCH/graph" "$SCRATCH/run"
cat > "$SCRATCH/storage.conf" <<CONF
[storage]
driver = "overlay"
graphroot = "$SCRATCH/graph"
runroot = "$SCRATCH/run"
CONF
export CONTAINERS_STORAGE_CONF="$SCRATCH/storage.conf"

# The Debian mirror apt uses here (one-line .list files or deb822 .sources), so that no host name is written
# in this script; the first one serving bookworm itself.
mirror=$(cat /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null \
           | awk '$1 == "deb" { for (i = 2; i <= NF; i++) if ($i ~ /^https?:/) { if ($(i+1) == "bookworm") { print $i; exit } } }')
if [ -z "$mirror" ]; then
  mirror=$(awk 'BEGIN { RS = "" } /Suites:[^\n]*bookworm( |\n|$)/ && !/bookworm-security/ {
                 for (i = 1; i <= NF; i++) if ($i == "URIs:") { print $(i+1); exit } }' /etc/apt/sources.list.d/*.sources 2>/dev/null)
fi
[ -n "$mirror" ] || { echo "docker-check: no bookworm mirror in apt's sources" >&2; exit 1; }
security=$(echo "$mirror" | sed 's#/debian/*$#/debian-security#')

if ! podman image exists debian:bookworm-slim; then
  step "base image: debootstrap bookworm from $mirror"
  debootstrap --variant=minbase bookworm "$SCRATCH/rootfs" "$mirror" > "$SCRATCH/debootstrap.log" 2>&1 \
    || { tail -20 "$SCRATCH/debootstrap.log"; exit 1; }
  printf 'deb %s bookworm main\ndeb %s bookworm-updates main\ndeb %s bookworm-security main\n' \
    "$mirror" "$mirror" "$security" > "$SCRATCH/rootfs/etc/apt/sources.list"
  tar -C "$SCRATCH/rootfs" -c . | podman import - debian:bookworm-slim
  rm -rf "$SCRATCH/rootfs"
fi

step "build: both stages, every test in the build stage"
start=$(date +%s)
buildah bud --isolation chroot --layers -f "$ROOT/docker/Dockerfile" -t granulab "$ROOT"
echo "built in $(( $(date +%s) - start )) s"

step "serve: the runtime image's granulabd on loopback"
mkdir -p "$SCRATCH/data" && chmod 777 "$SCRATCH/data"
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
CTR=$(buildah from localhost/granulab)
buildah run --isolation chroot -v "$SCRATCH/data:/data" "$CTR" \
  granulabd --host 127.0.0.1 --port "$port" --db /data/granulab.db > "$SCRATCH/daemon.log" 2>&1 &
DAEMON=$!
GRANULAB_SERVER="http://127.0.0.1:$port" python3 - "$ROOT" <<'PY'
import json, os, sys, time
sys.path.insert(0, os.path.join(sys.argv[1], "clients", "python"))
from granulab_client import Client
client = Client(os.environ["GRANULAB_SERVER"])
for _ in range(300):
    try:
        print("health:", client.health())
        break
    except Exception:
        time.sleep(0.1)
else:
    sys.exit("docker-check: the image's daemon never answered")
with open(os.path.join(sys.argv[1], "examples", "two_cube_f03.json")) as f:
    job = client.submit(json.load(f))
done = client.wait(job, timeout=600)
curve = client.curve(job)
rows = len(curve[curve["columns"][0]]) if curve.get("columns") else 0
print("job", job, done["status"] + ",", rows, "curve rows")
sys.exit(0 if rows > 0 else "docker-check: the job's curve is empty")
PY
echo "docker-check: the image builds, passes its tests and serves"
