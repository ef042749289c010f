#!/usr/bin/env bash
# Brings lavapipe (Mesa's software Vulkan driver) to a release that holds memory flat.
#
# Mesa's lavapipe before 23.0 leaks about 5 MB a frame in its queue thread (measured on Debian 12's
# 22.3.6; 25.0.7 holds memory flat). Debian 12's own archive carries Mesa 25.0.7 in the
# bookworm-backports suite. The same package holds the AMD and Intel Vulkan drivers and pulls the
# GL drivers along, so it is taken from backports only where that surprises nobody: as root, on
# Debian 12, on a machine with no GPU (CI, containers, cluster images). Everywhere else this script
# says what it found and prints the line that would upgrade, and changes nothing.
#
# RELIEF_KEEP_MESA=1 leaves the installed Mesa alone in every case. RELIEF_SETUP_DRY_RUN=1 says
# what would change and changes nothing; in a dry run RELIEF_SETUP_FACTS (space-separated
# `codename=`, `root=0|1`, `gpu=0|1`, `mesa=VERSION`, empty for none) stands in for the machine,
# which is how tests/setup_script.rs checks every decision below.
set -euo pipefail

min_version=23.0
backports_suite=bookworm-backports
backports_packages=(mesa-vulkan-drivers libdrm2 libdrm-amdgpu1)
dry_run=${RELIEF_SETUP_DRY_RUN:-0}

# A fact about the machine given by RELIEF_SETUP_FACTS, in a dry run only; fails when not given.
fact() {
    [[ $dry_run == 1 ]] || return 1
    local kv
    for kv in ${RELIEF_SETUP_FACTS:-}; do
        if [[ ${kv%%=*} == "$1" ]]; then
            echo "${kv#*=}"
            return 0
        fi
    done
    return 1
}

installed_version() {
    fact mesa || dpkg-query -W -f '${Version}' mesa-vulkan-drivers 2>/dev/null || true
}

have_gpu() {
    local gpu
    if gpu=$(fact gpu); then
        [[ $gpu == 1 ]]
        return
    fi
    compgen -G '/dev/dri/renderD*' >/dev/null || [[ -e /dev/nvidia0 || -e /proc/driver/nvidia/version ]]
}

is_root() {
    local root
    if root=$(fact root); then
        [[ $root == 1 ]]
        return
    fi
    [[ $(id -u) -eq 0 ]]
}

command -v dpkg >/dev/null 2>&1 || exit 0
codename=$(fact codename || (. /etc/os-release 2>/dev/null && echo "${VERSION_CODENAME:-}"))
say() { echo "relief setup: $*" >&2; }
version=$(installed_version)
if [[ -z $version ]]; then
    # Not installed yet: where the upgrade would be taken anyway, install from backports at once
    # rather than Debian 12's release first; elsewhere setup.sh installs the distribution's own.
    [[ $codename == bookworm && ${RELIEF_KEEP_MESA:-0} != 1 ]] && is_root && ! have_gpu || exit 0
    version="(none)"
elif dpkg --compare-versions "$version" ge "$min_version"; then
    exit 0
else
    say "lavapipe is Mesa $version, which leaks about 5 MB a frame (long runs grow without bound)"
fi
if [[ ${RELIEF_KEEP_MESA:-0} == 1 ]]; then
    say "RELIEF_KEEP_MESA=1: keeping it"
    exit 0
fi
if [[ $codename != bookworm ]]; then
    say "upgrade Mesa to $min_version or later from your distribution's updates (this script upgrades it on Debian 12 only)"
    exit 0
fi

sources_line="deb http://deb.debian.org/debian $backports_suite main"
upgrade_line="apt-get install -y -t $backports_suite ${backports_packages[*]}"
if ! is_root || have_gpu; then
    if have_gpu; then
        say "this machine has a GPU: its Mesa also holds the GL and GPU Vulkan drivers, so it is left alone"
    fi
    say "to upgrade lavapipe to Mesa 25 from Debian's own backports:"
    say "  echo '$sources_line' | sudo tee /etc/apt/sources.list.d/$backports_suite.list"
    say "  sudo apt-get update && sudo $upgrade_line"
    exit 0
fi

has_backports() {
    grep -rhsE "^[^#]*$backports_suite" /etc/apt/sources.list /etc/apt/sources.list.d/ >/dev/null
}
if [[ $dry_run == 1 ]]; then
    say "would add $backports_suite to /etc/apt/sources.list.d/$backports_suite.list unless listed"
    say "would run: apt-get update -qq"
    say "would run: apt-get install -y -qq --no-install-recommends -t $backports_suite ${backports_packages[*]}"
    exit 0
fi
export DEBIAN_FRONTEND=noninteractive
if ! has_backports; then
    say "adding $backports_suite to /etc/apt/sources.list.d/$backports_suite.list"
    echo "$sources_line" >"/etc/apt/sources.list.d/$backports_suite.list"
fi
apt-get update -qq
before=$(dpkg-query -W -f '${Package} ${Version}\n' | sort)
say "taking lavapipe from $backports_suite (no GPU here): $upgrade_line"
apt-get install -y -qq --no-install-recommends -t "$backports_suite" "${backports_packages[@]}" >/dev/null
after=$(dpkg-query -W -f '${Package} ${Version}\n' | sort)
say "packages changed (package: before -> after):"
join -a 2 -e '(none)' -o '0,1.2,2.2' <(echo "$before") <(echo "$after") |
    awk '$2 != $3 { printf "relief setup:   %s: %s -> %s\n", $1, $2, $3 }' >&2
say "lavapipe is now Mesa $(installed_version)"
