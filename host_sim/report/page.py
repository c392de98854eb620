"""The page every trueaxis-calibrate report shares: a title, a summary table
(what an integrator files), figures with a caption each (what a metrology
engineer reads), and tables. Plots are drawn by matplotlib (Debian's
python3-matplotlib) on the Agg backend, never by hand; a method's module
imports plt from here so that the backend is chosen before pyplot loads.
"""
import html
import os
import urllib.parse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

__all__ = ["Report", "fmt", "plt"]


class Report:
    def __init__(self, directory, title):
        self.directory = directory
        self.title = title
        self.parts = []
        self.figures = 0

    def record(self, rows, verdict, json_link):
        """The page's opening: the verdict, then the traceability rows, and a link to OUT.json."""
        body = "".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(v)}</td></tr>" for k, v in rows)
        self.parts.append(f"<p class='verdict verdict-{html.escape(verdict.split(',')[0])}'>Verdict: "
                          f"{html.escape(verdict)}</p><table class='summary record'>{body}</table>"
                          f"<p>The numbers: <a href='{html.escape(urllib.parse.quote(json_link))}'>"
                          f"{html.escape(json_link)}</a></p>")

    def summary(self, rows):
        body = "".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(v)}</td></tr>" for k, v in rows)
        self.parts.append(f"<h2>Summary</h2><table class='summary'>{body}</table>")

    def figure(self, fig, caption):
        self.figures += 1
        name = f"figure_{self.figures}.png"
        fig.tight_layout()
        fig.savefig(os.path.join(self.directory, name), dpi=110)
        plt.close(fig)
        self.parts.append(f"<figure><img src='{name}' alt='{html.escape(caption)}'>"
                          f"<figcaption>Figure {self.figures}. {html.escape(caption)}</figcaption></figure>")

    def table(self, title, headers, rows):
        head = "".join(f"<th>{html.escape(h)}</th>" for h in headers)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in r) + "</tr>" for r in rows)
        self.parts.append(f"<h2>{html.escape(title)}</h2><table><tr>{head}</tr>{body}</table>")

    def write(self):
        style = ("body{font-family:sans-serif;max-width:60em;margin:2em auto}"
                 "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:2px 8px;"
                 "text-align:right}table.summary th{text-align:left}figure{margin:1.5em 0}"
                 "img{max-width:100%}figcaption{font-size:90%;color:#333}"
                 ".verdict{font-size:140%;font-weight:bold}.verdict-fail{color:#a00}.verdict-warn{color:#a60}"
                 ".verdict-pass{color:#060}"
                 "@media print{@page{size:A4;margin:15mm}body{max-width:none;margin:0}"
                 "figure,table{page-break-inside:avoid}a{color:inherit}}")
        page = (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(self.title)}</title>"
                f"<style>{style}</style></head><body><h1>{html.escape(self.title)}</h1>"
                + "".join(self.parts) + "</body></html>\n")
        with open(os.path.join(self.directory, "index.html"), "w", encoding="utf-8") as f:
            f.write(page)


def fmt(v, digits=3):
    return f"{v:.{digits}f}"
