#!/usr/bin/env bash
# viewer_docScreenshots: runs tools/doc-screenshots.sh into OUT_DIR and checks that every
# barylab-viewer picture docs/user-guide.md shows was written (a non-empty PNG), so the guide's
# screenshot commands keep working and no picture is left without one.
#   check_doc_screenshots.sh SOURCE_DIR BUILD_DIR OUT_DIR
set -euo pipefail
SRC=$1 BUILD=$2 OUT=$3
rm -rf "$OUT"
"$SRC/tools/doc-screenshots.sh" "$OUT" "$BUILD"
missing=0
for image in $(grep -o 'images/viewer_[a-z0-9_]*\.png' "$SRC/docs/user-guide.md" | sort -u); do
  file=$OUT/${image#images/}
  if [ ! -s "$file" ] || [ "$(head -c 8 "$file" | od -An -tx1 | tr -d ' \n')" != "89504e470d0a1a0a" ]; then
    echo "missing or not a PNG: $file (shown by docs/user-guide.md as $image)" >&2
    missing=1
  fi
done
exit $missing
