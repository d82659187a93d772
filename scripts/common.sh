# Shared shell functions of the scripts in scripts/; sourced, not run.

log()
{
    printf '\n=== %s\n' "$*"
}

# install_packages WHO PACKAGE...: apt-get install the packages that are
# missing (none: nothing happens), with sudo when not root.
install_packages()
{
    local who=$1 missing=() pkg sudo=()
    shift
    local packages=("$@")
    if ! command -v dpkg-query > /dev/null || ! command -v apt-get > /dev/null; then
        echo "$who: not a Debian system; make sure these are installed: ${packages[*]}"
        return 0
    fi
    for pkg in "${packages[@]}"; do
        if ! dpkg-query -W -f='${Status}' "$pkg" 2> /dev/null | grep -q 'install ok installed'; then
            missing+=("$pkg")
        fi
    done
    if [ ${#missing[@]} -eq 0 ]; then
        echo "$who: all ${#packages[@]} packages are installed"
        return 0
    fi
    if [ "$(id -u)" -ne 0 ]; then
        if command -v sudo > /dev/null; then
            sudo=(sudo)
        else
            echo "$who: need root or sudo to install: ${missing[*]}" >&2
            return 1
        fi
    fi
    log "installing: ${missing[*]}"
    "${sudo[@]}" apt-get update &&
        "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y \
            --no-install-recommends "${missing[@]}"
}

