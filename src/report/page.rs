//! The page's frame: escaping, the style sheet (with its print rules: one section per page), the few lines of
//! script that sort a table by a click on its header, and the table and figure markup every section shares.

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

/// Sorts a table by the clicked header (numbers as numbers, text as text; a second click reverses). Each
/// `click=N` of the page's query clicks header N (from 0) of the first sortable table once the page opens, so a
/// headless browser can click a header (`index.html?click=4&click=4`: column 4, descending).
const SCRIPT: &str = "function sortBy(t,c,desc){const b=t.tBodies[0],rows=Array.from(b.rows),
n=s=>s.trim()!==''&&!isNaN(Number(s));rows.sort((x,y)=>{const p=x.cells[c].textContent,q=y.cells[c].textContent;
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
/// cell's text the CSV's.
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
        for cell in row {
            let _ = write!(out, "<td>{}</td>", escape(cell));
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
}
