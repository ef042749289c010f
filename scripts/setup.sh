#!/usr/bin/env bash
# Makes sure this machine can run relief: the Vulkan loader, lavapipe (Mesa's software Vulkan
# driver, used when there is no GPU) and the Khronos validation layer. Installs them through apt
# when missing and running as root; otherwise prints the exact install line and fails.
set -euo pipefail

packages=(libvulkan1 mesa-vulkan-drivers vulkan-validationlayers)

# Before the missing packages: on a machine where lavapipe comes from Debian 12's backports, it is
# installed from there at once; after them, an old one is upgraded or reported.
scripts_dir=$(dirname "${BASH_SOURCE[0]}")
"$scripts_dir/lavapipe.sh"

missing=()
# grep without -q reads all of ldconfig's output: with pipefail, -q's early exit would SIGPIPE
# ldconfig and make the check fail.
have_loader() {
    compgen -G '/usr/lib/*/libvulkan.so.1' >/dev/null || compgen -G '/usr/lib/libvulkan.so.1' >/dev/null ||
        /sbin/ldconfig -p 2>/dev/null | grep 'libvulkan\.so\.1' >/dev/null
}
have_icd() { compgen -G '/usr/share/vulkan/icd.d/*.json' >/dev/null || compgen -G '/etc/vulkan/icd.d/*.json' >/dev/null; }
have_layer() { [[ -e /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json ]]; }
have_loader || missing+=(libvulkan1)
have_icd || missing+=(mesa-vulkan-drivers)
have_layer || missing+=(vulkan-validationlayers)

if ((${#missing[@]} > 0)); then
    if ! command -v apt-get >/dev/null 2>&1; then
        echo "relief setup: missing ${missing[*]}; install the Vulkan loader, a driver (Mesa lavapipe) and the validation layer with your package manager" >&2
        exit 1
    fi
    if [[ $(id -u) -ne 0 ]]; then
        echo "relief setup: missing ${missing[*]}. Install them with:" >&2
        echo "  sudo apt-get update && sudo apt-get install -y ${packages[*]}" >&2
        exit 1
    fi
    echo "relief setup: installing ${missing[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null
fi

# Mesa's lavapipe before 23.0 leaks about 5 MB a frame (Debian 12 ships 22.3.6); Debian's own
# bookworm-backports suite carries 25.0.7, which holds memory flat and offers ray queries.
"$scripts_dir/lavapipe.sh"

# Xvfb and the X11 libraries the viewer's window (winit) loads at run time.
view_packages=(xvfb libx11-6 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0 libxcb1)
if ! command -v Xvfb >/dev/null 2>&1; then
    if [[ $(id -u) -eq 0 ]] && command -v apt-get >/dev/null 2>&1; then
        echo "relief setup: installing ${view_packages[*]} (for the relief view tests)" >&2
        export DEBIAN_FRONTEND=noninteractive
        { apt-get install -y -qq --no-install-recommends "${view_packages[@]}" >/dev/null 2>&1 ||
            { apt-get update -qq && apt-get install -y -qq --no-install-recommends "${view_packages[@]}" >/dev/null; }; } ||
            echo "relief setup: could not install xvfb; the relief view tests will be skipped" >&2
    else
        echo "relief setup: no Xvfb, so the relief view tests will be skipped; install it with:" >&2
        echo "  sudo apt-get install -y ${view_packages[*]}" >&2
    fi
fi

if ! command -v cargo >/dev/null 2>&1; then
    echo "relief setup: cargo not found; install Rust from https://rustup.rs" >&2
    exit 1
fi
