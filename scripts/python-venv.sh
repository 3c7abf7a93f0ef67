# Sourced by scripts that run Python with packages from PyPI (tests/server/run_pytest.sh,
# bench/mitsuba_compare.sh). ensure_venv DIR PACKAGE... makes a venv in DIR once and installs the
# packages into it; pip reaches the network only when the package list changed since the last
# install.
ensure_venv() {
    local venv="$1"
    shift
    # Debian ships venv (with ensurepip) apart from python3: install it when a venv cannot be made.
    if [ ! -x "$venv/bin/python" ] && ! python3 -m venv "$venv" 2>/dev/null; then
        rm -rf "$venv"
        local sudo_cmd=()
        if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
        echo "caustic: installing python3-venv" >&2
        export DEBIAN_FRONTEND=noninteractive
        "${sudo_cmd[@]}" apt-get update -qq
        "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends python3-venv >/dev/null
        python3 -m venv "$venv"
    fi
    local stamp="$venv/.caustic-requirements"
    if [ "$(cat "$stamp" 2>/dev/null)" != "$*" ]; then
        "$venv/bin/python" -m pip install --quiet --disable-pip-version-check "$@" >&2
        echo "$*" >"$stamp"
    fi
}
