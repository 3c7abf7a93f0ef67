#!/usr/bin/env bash
# Installs OpenImageIO for the image's build into PREFIX from the OpenImageIO project's own
# release on PyPI: the library from its wheel, the headers from the same release's source archive.
#
# Why: Debian's OpenImageIO is built with every format plugin, and loads OpenCV, GDAL, FFmpeg,
# OpenVDB and DCMTK with their own dependencies (about 330 MB of the image). The wheel's library
# links its formats in (OpenEXR, TIFF, PNG, JPEG, WebP, HDR among them, the ones Caustic reads and
# writes) and needs only zlib and the C++ runtime: 13 MB. It is built by the project's CI
# (manylinux_2_28, C++17, the C++11 string ABI, SSE2 only, without TBB), so it runs on any x86-64 Debian 12.
# Debian's source package cannot be fetched where the image is built (its mirror serves binary
# packages only), and OpenImageIO 3 built from source needs OpenColorIO 2.2, newer than Debian 12's.
#
# The two files are pinned by their SHA-256. The headers need what CMake would have configured:
# oiioversion.h from its template, and the fmt headers OpenImageIO bundles (Debian's libfmt-dev;
# OpenImageIO uses fmt header-only).
# usage: oiio-from-wheel.sh PREFIX
set -euo pipefail
prefix=$1
version=3.0.21.0
wheel=openimageio-$version-cp311-cp311-manylinux_2_27_x86_64.manylinux_2_28_x86_64.whl
wheel_sha256=26e9183ec3538481b3bf194c6614a79cc19021c80472e10c2f003cd928aca70d
source=openimageio-$version.tar.gz
source_sha256=404540688f14a770de37fc545aa7d17bec222e4bd44aefe39b0f6393eafcf086

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
# The files' addresses from PyPI's simple index (PEP 503); a TLS-intercepting proxy's CA may be
# given in SSL_CERT_FILE.
python3 - "$wheel" "$source" <<'PY'
import re, sys, urllib.request
index = urllib.request.urlopen("https://pypi.org/simple/openimageio/", timeout=120).read().decode()
for name in sys.argv[1:]:
    url = re.search(r'href="([^"#]*/' + re.escape(name) + r')[#"]', index).group(1)
    with urllib.request.urlopen(url, timeout=600) as r, open(name, "wb") as f:
        f.write(r.read())
PY
echo "$wheel_sha256  $wheel" | sha256sum -c --quiet
echo "$source_sha256  $source" | sha256sum -c --quiet

python3 -m zipfile -e "$wheel" wheel
tar xzf "$source"
major=${version%%.*} rest=${version#*.}
minor=${rest%%.*} rest=${rest#*.}
patch=${rest%%.*} tweak=${rest#*.}

mkdir -p "$prefix/lib/pkgconfig" "$prefix/include" "$prefix/share/doc/openimageio"
cp -a "openimageio-$version/src/include/OpenImageIO" "$prefix/include/"
header="$prefix/include/OpenImageIO"
sed -e "s/@PROJECT_VERSION_MAJOR@/$major/; s/@PROJECT_VERSION_MINOR@/$minor/" \
    -e "s/@PROJECT_VERSION_PATCH@/$patch/; s/@PROJECT_VERSION_TWEAK@/$tweak/" \
    -e 's/@PROJECT_VERSION_RELEASE_TYPE@//' \
    -e "s/@PROJ_NAMESPACE_V@/OpenImageIO_v${major}_${minor}/g; s/@PROJ_NAME@/OIIO/g" \
    -e "s/@Imath_VERSION_MAJOR@/3/; s/@Imath_VERSION_MINOR@/1/; s/@CMAKE_CXX_STANDARD@/17/g" \
    -e 's/^#cmakedefine01 OIIO_TBB$/#define OIIO_TBB 0/' \
    "$header/oiioversion.h.in" >"$header/oiioversion.h"
rm "$header/oiioversion.h.in"
if grep -n -e "@[A-Za-z_]*@" -e "#cmakedefine" "$header/oiioversion.h"; then
    echo "oiio-from-wheel: oiioversion.h has a value not filled in" >&2
    exit 1
fi
mkdir -p "$header/detail/fmt"
cp /usr/include/fmt/*.h "$header/detail/fmt/"

so=libOpenImageIO.so.$major.$minor.$patch util=libOpenImageIO_Util.so.$major.$minor.$patch
for lib in "$so" "$util"; do
    install -m 644 "wheel/OpenImageIO/lib/$lib" "$prefix/lib/"
    ln -sf "$lib" "$prefix/lib/${lib%%.so.*}.so" # the name the linker looks for; the soname is $lib
done
cp "openimageio-$version/LICENSE.md" "openimageio-$version/THIRD-PARTY.md" \
    "$prefix/share/doc/openimageio/"
cat >"$prefix/lib/pkgconfig/OpenImageIO.pc" <<PC
prefix=$prefix
Name: OpenImageIO
Description: OpenImageIO $version (the PyPI wheel's library)
Version: $version
Requires: Imath
Libs: -L\${prefix}/lib -Wl,-rpath,\${prefix}/lib -lOpenImageIO -lOpenImageIO_Util
Cflags: -I\${prefix}/include
PC
echo "oiio-from-wheel: OpenImageIO $version in $prefix ($(du -sh "$prefix/lib" | cut -f1) of libraries)" >&2
