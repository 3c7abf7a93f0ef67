#!/usr/bin/env bash
# docs/settings.md is exactly what `caustic settings --markdown` generates from the settings table
# (renderer/render/settings_table.cpp), so the reference cannot drift from the code.
# usage: check_settings_reference.sh CAUSTIC_BINARY SOURCE_DIR
set -euo pipefail
caustic=$1
page=$2/docs/settings.md
if ! diff -u "$page" <("$caustic" settings --markdown); then
    echo "docs/settings.md differs from the settings table (diff above: - the page, + the table)." >&2
    echo "Regenerate it: build/cli/caustic settings --markdown > docs/settings.md" >&2
    exit 1
fi
echo "docs/settings.md matches the settings table"
