//! The page's frame: escaping, the style sheet (with its print rules: one section per page), the few lines of
//! script that sort a table by a click on its header, the table and figure markup every section shares, and
//! numbers as a reader is shown them ([`readable`], [`shown`]: the digits that mean something; the CSV and JSON
//! files beside the page keep every digit, and a table cell keeps it in its `title`).

use super::data::Table;
use std::fmt::Write as _;

/// `text` with `&`, `<`, `>` and quotes escaped, for element text and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// Significant digits a reader is shown of a measured figure.
pub const DIGITS: usize = 4;
/// Significant digits of a time in milliseconds (timings vary by more than 1 % from run to run).
pub const TIME_DIGITS: usize = 3;

/// `x` rounded to `digits` significant digits, without trailing zeros or an exponent (`0.05675050708926869` →
/// `0.05675`, `3.501971` → `3.5` at 3); a value of `digits` or more integral digits keeps them all (`16777216`),
/// and a value that is not finite reads as Rust writes it (`inf`, `NaN`).
pub fn readable(x: f64, digits: usize) -> String {
    if !x.is_finite() || x == 0.0 {
        return x.to_string();
    }
    let magnitude = x.abs().log10().floor() as i64;
    let decimals = (digits as i64 - 1 - magnitude).max(0) as usize;
    let text = format!("{x:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// A CSV cell of `column` as a reader is shown it: a number with a fraction or an exponent [`readable`]
/// ([`TIME_DIGITS`] in a time column, one with an `ms` word in its name, [`DIGITS`] elsewhere); an integer,
/// text and an empty cell as they are.
pub fn shown(column: &str, cell: &str) -> String {
    let fractional = cell.contains(['.', 'e', 'E']);
    match cell.parse::<f64>() {
        Ok(x) if fractional && x.is_finite() => {
            let time = column.split(['_', ' ']).any(|w| w.eq_ignore_ascii_case("ms"));
            readable(x, if time { TIME_DIGITS } else { DIGITS })
        }
        _ => cell.to_string(),
    }
}

const STYLE: &str =
    "body{font-family:system-ui,sans-serif;margin:1.5em auto;max-width:75em;padding:0 1em;color:#222}
h1{font-size:1.6em}h2{border-bottom:1px solid #ccc;padding-bottom:.2em}
table{border-collapse:collapse;font-size:.8em;margin:.5em 0}
caption{text-align:left;font-weight:bold;padding:.2em 0}
th,td{border:1px solid #ccc;padding:.15em .4em;text-align:right;white-space:nowrap}
th{background:#eee;cursor:pointer;position:sticky;top:0}
th[aria-sort=ascending]::after{content:' \\25B2'}th[aria-sort=descending]::after{content:' \\25BC'}
td:first-child,th:first-child{text-align:left}
#claims td,#claims th{white-space:normal;text-align:left;min-width:8em}
.scroll{overflow-x:auto;max-width:100%}
figure{margin:1em 0}figure img{max-width:100%;height:auto;border:1px solid #ddd}
figcaption{font-size:.85em;color:#555}
.grid{display:grid;grid-template-columns:repeat(4,1fr);gap:.5em}.grid3{display:grid;grid-template-columns:repeat(3,1fr);gap:.5em}.grid figure,.grid3 figure{margin:0}
h3{font-size:1.05em;margin:1em 0 .2em}
dl{display:grid;grid-template-columns:max-content auto;gap:.2em 1em}dt{font-weight:bold}dd{margin:0}
code{background:#f4f4f4;padding:.1em .3em;white-space:pre-wrap;word-break:break-all}
.holds{color:#176b2c;font-weight:bold}.fails{color:#a3181a;font-weight:bold}
@media print{body{max-width:none}section{break-after:page}section:last-of-type{break-after:auto}
th{position:static}.scroll{overflow:visible}a{color:inherit;text-decoration:none}}";

/// Sorts a table by the clicked header (numbers as numbers, text as text, a rounded cell by the whole number in
/// its `title`; a second click reverses). Each
/// `click=N` of the page's query clicks header N (from 0) of the first sortable table once the page opens, so a
/// headless browser can click a header (`index.html?click=4&click=4`: column 4, descending).
const SCRIPT: &str = "function sortBy(t,c,desc){const b=t.tBodies[0],rows=Array.from(b.rows),
n=s=>s.trim()!==''&&!isNaN(Number(s));rows.sort((x,y)=>{const v=e=>e.title||e.textContent,p=v(x.cells[c]),q=v(y.cells[c]);
const r=n(p)&&n(q)?Number(p)-Number(q):p.localeCompare(q);return desc?-r:r});rows.forEach(r=>b.appendChild(r));
Array.from(t.tHead.rows[0].cells).forEach((h,i)=>h.setAttribute('aria-sort',i===c?(desc?'descending':'ascending'):'none'))}
document.querySelectorAll('table.sortable').forEach(t=>Array.from(t.tHead.rows[0].cells).forEach((h,i)=>
h.addEventListener('click',()=>sortBy(t,i,h.getAttribute('aria-sort')==='ascending'))));
const first=document.querySelector('table.sortable');
if(first)new URLSearchParams(location.search).getAll('click').forEach(c=>first.tHead.rows[0].cells[Number(c)].click());";

/// The whole page around `body`.
pub fn document(title: &str, body: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>{}</title>\n\
         <style>\n{STYLE}\n</style>\n</head>\n<body>\n{body}<script>\n{SCRIPT}\n</script>\n</body>\n</html>\n",
        escape(title)
    )
}

/// A section with its id, heading and content.
pub fn section(id: &str, heading: &str, content: &str) -> String {
    format!(
        "<section id=\"{id}\" aria-labelledby=\"{id}-h\">\n<h2 id=\"{id}-h\">{}</h2>\n{content}</section>\n",
        escape(heading)
    )
}

/// `table` whole as a sortable HTML table with the id `id`: a header cell per column, a cell per CSV cell, each
/// cell's text the CSV's as a reader is shown it ([`shown`]), the CSV's whole text in its `title` where the two
/// differ.
pub fn sortable_table(id: &str, caption: &str, table: &Table) -> String {
    let mut out = format!(
        "<div class=\"scroll\"><table id=\"{id}\" class=\"sortable\">\n<caption>{}</caption>\n<thead><tr>",
        escape(caption)
    );
    for h in &table.header {
        let _ = write!(out, "<th scope=\"col\" aria-sort=\"none\">{}</th>", escape(h));
    }
    out.push_str("</tr></thead>\n<tbody>\n");
    for row in &table.rows {
        out.push_str("<tr>");
        for (cell, column) in row.iter().zip(&table.header) {
            let text = shown(column, cell);
            if text == *cell {
                let _ = write!(out, "<td>{}</td>", escape(cell));
            } else {
                let _ = write!(out, "<td title=\"{}\">{}</td>", escape(cell), escape(&text));
            }
        }
        out.push_str("</tr>\n");
    }
    out.push_str("</tbody>\n</table></div>\n");
    out
}

/// A figure of the image at `src` (relative to the page) with its alt text and caption.
pub fn figure(src: &str, alt: &str, caption: &str) -> String {
    format!(
        "<figure><img src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n",
        escape(src),
        escape(alt),
        escape(caption)
    )
}

/// A link to a file of the report.
pub fn link(href: &str, text: &str) -> String {
    format!("<a href=\"{}\">{}</a>", escape(href), escape(text))
}

/// A definition list of `(term, value)` pairs.
pub fn facts(pairs: &[(&str, String)]) -> String {
    let mut out = String::from("<dl>\n");
    for (k, v) in pairs {
        let _ = writeln!(out, "<dt>{}</dt><dd>{}</dd>", escape(k), escape(v));
    }
    out.push_str("</dl>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markup_in_text_is_escaped() {
        assert_eq!(escape("a<b & \"c\"'"), "a&lt;b &amp; &quot;c&quot;&#39;");
    }

    #[test]
    fn a_reader_is_shown_the_significant_digits() {
        for (x, digits, text) in [
            (0.05675050708926869, 4, "0.05675"),
            (0.0125569467718559, 4, "0.01256"),
            (6.802864363942713, 4, "6.803"),
            (3.501971, 3, "3.5"),
            (12.3456, 3, "12.3"),
            (-0.000123456, 4, "-0.0001235"),
            (9.99996, 4, "10"),
            (16777216.0, 4, "16777216"),
            (1234.6, 3, "1235"),
            (0.0, 4, "0"),
            (f64::INFINITY, 4, "inf"),
        ] {
            assert_eq!(readable(x, digits), text, "{x} at {digits}");
        }
        assert_eq!(shown("map_error", "0.05675050708926869"), "0.05675");
        assert_eq!(shown("gpu_ms_median", "3.501971"), "3.5");
        assert_eq!(shown("gpu_ms", "3.567"), "3.57");
        assert_eq!(shown("flip", "1.5e-7"), "0.00000015");
        for kept in ["16777216", "3", "", "inf", "NaN", "dom:layers=3", "true"] {
            assert_eq!(shown("flip", kept), kept);
        }
    }

    /// A cell the page rounds keeps the CSV's text in its `title`; a cell it shows whole has none; markup in
    /// either is escaped.
    #[test]
    fn a_table_shows_rounded_cells_and_keeps_the_whole_number() {
        let table = Table {
            file: "t.csv".into(),
            header: vec!["label".into(), "gpu_ms".into(), "memory_bytes".into()],
            rows: vec![vec!["a<\"b\"".into(), "3.501971".into(), "1024".into()]],
        };
        let html = sortable_table("t", "caption", &table);
        assert!(
            html.contains("<tr><td>a&lt;&quot;b&quot;</td><td title=\"3.501971\">3.5</td><td>1024</td></tr>"),
            "{html}"
        );
    }
}
