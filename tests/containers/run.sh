#!/usr/bin/env bash
# The container tests (CTest label "containers"): builds the image from docker/Dockerfile
# unchanged, and a stand-in for the official PostgreSQL image (tests/containers/postgres/), then
# runs test_containers.py against them with podman, as ../shared/containers.md describes for a CI
# machine without a Docker engine or a registry. Prints how long each step took.
# usage: tests/containers/run.sh [pytest options, e.g. -k scale -v]
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
# Rootful podman, as on the CI machine (rootless podman needs subordinate ids set up).
if [ "$(id -u)" -ne 0 ]; then exec sudo -E bash "$0" "$@"; fi

work=${CAUSTIC_CONTAINER_WORK:-/var/tmp/caustic-containers}
mkdir -p "$work"
# Podman's defaults fail there: crun refuses hybrid cgroups, and the default ulimits exceed the
# hard limits.
cat >"$work/containers.conf" <<'CONF'
[containers]
default_ulimits = ["nofile=1024:1024", "nproc=4096:4096"]
[engine]
runtime = "runc"
CONF
export CONTAINERS_CONF="$work/containers.conf"

step() { echo "caustic: $1 in $(($(date +%s) - $2)) s" >&2; }

# No image can be pulled: the base image is made from Debian's packages, under the name the
# Dockerfiles use (a real one, if present, is used as it is).
base=docker.io/library/debian:bookworm-slim
if ! podman image exists "$base"; then
    start=$(date +%s)
    mirror=$(sed -n 's/^URIs: //p' /etc/apt/sources.list.d/debian.sources 2>/dev/null | head -n 1)
    [ -n "$mirror" ] || mirror=$(awk '$1 == "deb" { print $2; exit }' /etc/apt/sources.list)
    rootfs=$(mktemp -d "$work/rootfs.XXXXXX")
    debootstrap --variant=minbase bookworm "$rootfs" "$mirror" >"$work/debootstrap.log" 2>&1 ||
        { tail -n 20 "$work/debootstrap.log" >&2; exit 1; }
    # Slim as the official image is: no package lists or cached packages, and dpkg told to skip
    # documentation, manual pages and translations (debuerreotype's "slim" rules).
    cat >"$rootfs/etc/dpkg/dpkg.cfg.d/docker-slim" <<'SLIM'
path-exclude /usr/share/doc/*
path-include /usr/share/doc/*/copyright
path-exclude /usr/share/groff/*
path-exclude /usr/share/info/*
path-exclude /usr/share/linda/*
path-exclude /usr/share/lintian/overrides/*
path-exclude /usr/share/locale/*
path-exclude /usr/share/man/*
SLIM
    rm -rf "$rootfs"/var/cache/apt/*.bin "$rootfs"/var/cache/apt/archives/*.deb \
        "$rootfs"/var/lib/apt/lists/* "$rootfs"/usr/share/locale/* "$rootfs"/usr/share/man/* \
        "$rootfs"/usr/share/info/*
    find "$rootfs/usr/share/doc" -mindepth 1 -not -name copyright -not -type d -delete
    tar -C "$rootfs" -c . | podman import - "$base" >/dev/null
    rm -rf "$rootfs"
    step "made the base image $base with debootstrap" "$start"
fi

start=$(date +%s)
# --format docker: the OCI format has no HEALTHCHECK.
# The machine's CA bundle: the builder fetches OpenImageIO over HTTPS, through this machine's
# proxy when it has one.
podman build --pull=never --network host --format docker -f "$repo/docker/Dockerfile" \
    --secret id=ca_bundle,src=/etc/ssl/certs/ca-certificates.crt \
    -t caustic:latest "$repo" >"$work/build.log" 2>&1 ||
    { tail -n 40 "$work/build.log" >&2; exit 1; }
step "built caustic:latest from docker/Dockerfile" "$start"
size() { podman image inspect "$1" --format '{{.Size}}' | awk '{ printf "%.0f MB", $1 / 1e6 }'; }
echo "caustic: image caustic:latest $(size caustic:latest) (base image $(size "$base"))" >&2

# The official image cannot be pulled: a stand-in under its name (tests/containers/postgres/).
start=$(date +%s)
podman build --pull=never --network host -t docker.io/library/postgres:15 \
    "$repo/tests/containers/postgres" >"$work/postgres-build.log" 2>&1 ||
    { tail -n 40 "$work/postgres-build.log" >&2; exit 1; }
step "built the stand-in docker.io/library/postgres:15" "$start"

source "$repo/scripts/python-venv.sh"
ensure_venv "$work/venv" pytest==8.3.5 pytest-timeout==2.3.1 requests==2.32.3
start=$(date +%s)
cd "$repo/tests/containers"
status=0
"$work/venv/bin/python" -m pytest -p no:cacheprovider -v "$@" test_containers.py || status=$?
step "ran the container tests" "$start"
exit $status
