# Shared by tools/run and tools/test: make sure a Vulkan driver is present.
# On a machine without a GPU driver this installs Mesa's lavapipe (CPU).

have_vulkan_icd() {
    compgen -G "/usr/share/vulkan/icd.d/*.json" >/dev/null || compgen -G "/etc/vulkan/icd.d/*.json" >/dev/null
}

apt_install() {
    local sudo=""
    if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
    if ! $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y "$@"; then
        $sudo apt-get update && $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y "$@"
    fi
}

ensure_vulkan() {
    if ! have_vulkan_icd; then
        echo "tools: no Vulkan driver found; installing mesa-vulkan-drivers (lavapipe)" >&2
        apt_install mesa-vulkan-drivers
    fi
    # Mesa also exposes a GL llvmpipe adapter; glint wants the Vulkan one.
    export WGPU_BACKEND="${WGPU_BACKEND:-vulkan}"
}

ensure_cxx() {
    # nv-flip builds FLIP's C++ sources.
    if ! command -v g++ >/dev/null 2>&1; then
        apt_install g++
    fi
}

ensure_xvfb() {
    # The viewer's tests run a window under Xvfb and drive it with xdotool.
    if ! command -v xvfb-run >/dev/null 2>&1; then
        apt_install xvfb
    fi
    if ! command -v xdotool >/dev/null 2>&1; then
        apt_install xdotool
    fi
}

# The median frame time `glint render` prints, read from its output on stdin.
render_median_ms() {
    sed -n 's/.*median \([0-9.]*\) ms\/frame.*/\1/p'
}

# The median of the numbers given as arguments (the upper one of an even count).
median_of() {
    printf '%s\n' "$@" | sort -n | awk '{ v[NR] = $1 } END { printf "%s", v[int((NR + 1) / 2)] }'
}
