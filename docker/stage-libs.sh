#!/usr/bin/env bash
# Copies the shared libraries BINARY loads (its ldd closure) into STAGING at their paths, with
# each one's Debian copyright file and a manifest of package versions
# (STAGING/usr/share/caustic/libraries.txt), leaving out the libraries of Debian's required
# packages, which every Debian base image has. The runtime stage of docker/Dockerfile copies
# STAGING: installing the same libraries as packages would also install what those packages
# depend on but the binary never loads (OpenImageIO's package brings Mesa with LLVM, GDAL and PROJ
# data: over 400 MB).
# A library no package owns is copied only from a PREFIX given (docker/oiio-from-wheel.sh's
# OpenImageIO), with PREFIX/share/doc and the versions its pkg-config files name.
# usage: stage-libs.sh BINARY STAGING [PREFIX...]
set -euo pipefail
binary=$1 staging=$2
shift 2
prefixes=("$@")

if ldd "$binary" | grep "not found"; then
    echo "stage-libs: $binary needs libraries this machine does not have" >&2
    exit 1
fi
manifest="$staging/usr/share/caustic/libraries.txt"
mkdir -p "$(dirname "$manifest")"
ldd "$binary" | awk '$2 == "=>" && $3 ~ /^\// { print $3 }' | sort -u | while read -r lib; do
    # The canonical folder (/lib is /usr/lib on Debian 12): copying into /lib would replace the
    # base image's symbolic link with a folder.
    path="$(readlink -f "$(dirname "$lib")")/$(basename "$lib")"
    # (update-alternatives links, such as libblas.so.3, belong to no package; their target does)
    owner=$(dpkg -S "$lib" 2>/dev/null || dpkg -S "$path" 2>/dev/null ||
        dpkg -S "$(readlink -f "$lib")" 2>/dev/null || true)
    package=${owner%%:*}
    if [ -z "$package" ]; then
        for prefix in "${prefixes[@]}"; do
            case "$path" in "$prefix"/*) package=prefix:$prefix ;; esac
        done
    fi
    if [ -z "$package" ]; then
        echo "stage-libs: no package owns $lib" >&2
        exit 1
    fi
    if [ "${package%%:*}" = prefix ]; then
        prefix=${package#prefix:}
        install -D -m 644 "$(readlink -f "$lib")" "$staging$path"
        mkdir -p "$staging$prefix/share"
        cp -a "$prefix/share/doc" "$staging$prefix/share/"
        for pc in "$prefix"/lib/pkgconfig/*.pc; do
            sed -n "s/^Name: //p; s/^Version: /=/p" "$pc" | paste -sd '' >>"$manifest"
        done
        continue
    fi
    [ "$(dpkg-query -W -f '${Priority}' "$package")" = required ] && continue
    install -D -m 644 "$(readlink -f "$lib")" "$staging$path"
    copyright=/usr/share/doc/$package/copyright
    [ -f "$copyright" ] && install -D -m 644 "$copyright" "$staging$copyright"
    dpkg-query -W -f '${Package}=${Version}\n' "$package" >>"$manifest"
done
sort -u -o "$manifest" "$manifest"
echo "stage-libs: $(wc -l <"$manifest") packages' libraries, $(du -sh "$staging" | cut -f1)" >&2
