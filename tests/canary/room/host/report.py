"""The canary's report page (trueaxis_report.py draws it for
`trueaxis-calibrate canary --report DIR`)."""

TITLE = "Canary"


def draw(data, report):
    report.summary([("sum", format(data["sum"], ".6g"))])
    report.table("The canary's result", ["figure", "value"], [["sum", format(data["sum"], ".6g")]])
