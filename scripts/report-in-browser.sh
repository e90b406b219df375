#!/bin/sh
# Opens a `hairlab report` page (DIR/index.html) from disk in headless Chromium (Debian's `chromium` package:
# apt-get install -y chromium), with no network, and saves screenshots into SHOTS (default: DIR-browser):
#   page.png         the page as it opens (1280 px wide, the top 3000 px)
#   sorted.png       after a click on the results table's "gpu_ms_median" header, then a second (descending),
#                    when the page has that table
#   page.pdf         the page printed (its print style sheet starts each section on a new page, so the PDF has
#                    at least as many pages as the page has sections; checked here)
# The click: the page's own script clicks header N of its first sortable table for each `click=N` in the query
# (`index.html?click=4&click=4`), through the same click listener a mouse click reaches. Chromium's --dump-dom of
# that page is then checked here: the table's rows must be in descending order of that column, the header marked
# aria-sort="descending". Exits non-zero when the page does not load, sort, or the order is wrong.
# Usage: scripts/report-in-browser.sh DIR [SHOTS]
set -eu
dir=$(cd "${1:?usage: $0 DIR [SHOTS]}" && pwd)
shots=${2:-${dir%/}-browser}
mkdir -p "$shots"
shots=$(cd "$shots" && pwd)
page="file://$dir/index.html"
[ -f "$dir/index.html" ] || { echo "$dir/index.html: no report here" >&2; exit 1; }
browser=$(command -v chromium || command -v chromium-browser || true)
[ -n "$browser" ] || { echo "no chromium: apt-get install -y chromium" >&2; exit 1; }
# No network at all: a page that tried to fetch anything would show it broken.
run() {
    "$browser" --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run \
        --proxy-server=127.0.0.1:9 --proxy-bypass-list='<-loopback>' --window-size=1280,3000 "$@" 2>/dev/null
}
run --screenshot="$shots/page.png" "$page"
if [ -f "$dir/data/shadows/results.csv" ]; then
    column=$(python3 -c 'import csv,sys; print(next(csv.reader(open(sys.argv[1]))).index("gpu_ms_median"))' \
        "$dir/data/shadows/results.csv")
    run --screenshot="$shots/sorted.png" "$page?click=$column&click=$column"
    run --dump-dom "$page?click=$column&click=$column" > "$shots/sorted.html"
    python3 - "$shots/sorted.html" "$column" <<'EOF'
import html.parser, sys
class Rows(html.parser.HTMLParser):
    def __init__(self):
        super().__init__(); self.table = False; self.rows = []; self.cell = None; self.sort = []
    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "table" and a.get("id") == "results": self.table = True
        if self.table and tag == "th": self.sort.append(a.get("aria-sort"))
        if self.table and tag == "tr": self.rows.append([])
        if self.table and tag == "td": self.cell = ""
    def handle_endtag(self, tag):
        if tag == "table": self.table = False
        if self.table and tag == "td": self.rows[-1].append(self.cell); self.cell = None
    def handle_data(self, data):
        if self.cell is not None: self.cell += data
p = Rows(); p.feed(open(sys.argv[1]).read())
c = int(sys.argv[2])
values = [float(r[c]) for r in p.rows if r]
assert p.sort[c] == "descending", f"header {c} is {p.sort[c]!r}, not descending"
assert values == sorted(values, reverse=True), f"not sorted: {values}"
print(f"sorted by column {c} descending in Chromium: {values}")
EOF
else
    echo "no results table (data/shadows/results.csv): sorting not checked"
fi
run --no-pdf-header-footer --print-to-pdf="$shots/page.pdf" "$page"
sections=$(grep -c '<section ' "$dir/index.html")
pages=$(python3 -c 'import re,sys; print(len(re.findall(rb"/Type\s*/Page(?![a-z])", open(sys.argv[1],"rb").read())))' "$shots/page.pdf")
[ "$pages" -ge "$sections" ] || { echo "printed on $pages pages, fewer than its $sections sections" >&2; exit 1; }
echo "printed: $pages pages for $sections sections"
echo "screenshots and print: $(ls "$shots"/*.png "$shots"/*.pdf | tr '\n' ' ')"
