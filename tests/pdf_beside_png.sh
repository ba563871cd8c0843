#!/usr/bin/env sh
# pdf_beside_png.sh DIR: every figure DIR/*.png has its PDF beside it (the default GRAINLAB_FIGURE_FORMATS, png,pdf),
# a PDF file by its first bytes; prints how many. The tests write PNG alone but for the ones that check this.
n=0
for f in "$1"/*.png; do
  [ -e "$f" ] || break
  head -c 5 "${f%.png}.pdf" 2> /dev/null | grep -q '^%PDF-' || { echo "no PDF beside $f"; exit 1; }
  n=$((n + 1))
done
[ "$n" -gt 0 ] || { echo "no figure in $1"; exit 1; }
echo "$n figures in PNG and PDF"
