# Sourced by tools that take a file from a Debian package without
# installing it (tools/lavapipe-backport, tools/scanned-mesh): fetches the
# package's .deb, checked against the archive's signed index, and prints
# its path. Nothing is installed and apt is not touched.
#   source tools/debian-deb.sh
#   deb=$(debian_deb bookworm-backports mesa-vulkan-drivers target/x) || exit 1
# DEBIAN_MIRROR picks another mirror (default deb.debian.org).

debian_deb_fail() { echo "debian_deb: $*" >&2; return 1; }

# debian_deb SUITE PACKAGE DIR: the .deb of PACKAGE in SUITE's main
# component for this machine's architecture, downloaded into DIR (kept
# there and reused while it matches the index).
debian_deb() {
    local suite=$1 package=$2 dir=$3
    local tool
    for tool in dpkg-deb dpkg gpgv curl xz awk sha256sum; do
        command -v "$tool" >/dev/null || { debian_deb_fail "needs $tool (a Debian system)"; return 1; }
    done
    local keyring=/usr/share/keyrings/debian-archive-keyring.gpg
    [ -f "$keyring" ] || { debian_deb_fail "needs Debian's archive keyring ($keyring, package debian-archive-keyring)"; return 1; }
    local mirror=${DEBIAN_MIRROR:-https://deb.debian.org/debian}
    local arch
    arch=$(dpkg --print-architecture)
    mkdir -p "$dir"

    # The release file, signed by the archive's keys; it gives the index's hash.
    local release="$mirror/dists/$suite"
    curl -fsS -o "$dir/InRelease" "$release/InRelease" || { debian_deb_fail "cannot read $release/InRelease"; return 1; }
    gpgv --keyring "$keyring" --output "$dir/Release" "$dir/InRelease" 2>/dev/null ||
        { debian_deb_fail "$release/InRelease is not signed by Debian's archive keys"; return 1; }
    local entry="main/binary-$arch/Packages.xz"
    local index_sum
    index_sum=$(awk -v e="$entry" '/^SHA256:/ { s = 1; next } /^[^ ]/ { s = 0 } s && $3 == e { print $1; exit }' "$dir/Release")
    [ -n "$index_sum" ] || { debian_deb_fail "the release file lists no $entry"; return 1; }
    curl -fsS -o "$dir/Packages.xz" "$release/$entry" || { debian_deb_fail "cannot read $release/$entry"; return 1; }
    echo "$index_sum  $dir/Packages.xz" | sha256sum -c --quiet - >/dev/null 2>&1 ||
        { debian_deb_fail "$entry does not match the signed release file"; return 1; }
    xz -dc "$dir/Packages.xz" >"$dir/Packages" || { debian_deb_fail "cannot unpack $entry"; return 1; }

    # The package's file in the pool and that file's SHA-256, from the index.
    local stanza file sum
    stanza=$(awk -v want="$package" '
        function out() { if (p && f != "") { print f, s; found = 1; exit } }
        /^Package: / { p = ($2 == want) }
        p && /^Filename: / { f = $2 }
        p && /^SHA256: / { s = $2 }
        /^$/ { out() }
        END { if (!found) out() }' "$dir/Packages")
    read -r file sum <<<"$stanza" || true
    [ -n "${file:-}" ] && [ -n "${sum:-}" ] || { debian_deb_fail "$suite has no $package for $arch"; return 1; }
    local deb
    deb="$dir/$(basename "$file")"
    if ! echo "$sum  $deb" | sha256sum -c --quiet - >/dev/null 2>&1; then
        curl -fsS -o "$deb" "$mirror/$file" || { debian_deb_fail "cannot download $mirror/$file"; return 1; }
        echo "$sum  $deb" | sha256sum -c --quiet - >/dev/null 2>&1 ||
            { debian_deb_fail "$deb does not match the signed index"; return 1; }
    fi
    echo "$deb"
}
