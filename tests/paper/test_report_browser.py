"""The report page as a person sees it: headless Chromium loads ``index.html``
(the browser: ``tests/browser_util.py``)."""

from browser_util import _request, needs_browser, webdriver  # noqa: F401 (fixture)

pytestmark = needs_browser

_CHECK = """
const imgs = Array.from(document.images).map(
    i => ({src: i.getAttribute('src'), complete: i.complete, w: i.naturalWidth}));
const tables = Array.from(document.querySelectorAll('table')).map(
    t => ({id: t.id, rows: t.querySelectorAll('tbody tr').length,
           caption: t.caption ? t.caption.textContent : ''}));
const captions = Array.from(document.querySelectorAll('figcaption')).length;
return {title: document.title, imgs: imgs, tables: tables, captions: captions};
"""


def test_every_image_loads_and_every_table_is_there(report, webdriver):
    out = report[0]
    _request("POST", f"{webdriver}/url", {"url": (out / "index.html").resolve().as_uri()})
    page = _request("POST", f"{webdriver}/execute/sync", {"script": _CHECK, "args": []})["value"]
    assert "viscontact" in page["title"]
    srcs = sorted(i["src"] for i in page["imgs"])
    assert srcs == [f"fig{i:02d}.png" for i in range(2, 13)]
    for img in page["imgs"]:
        assert img["complete"] and img["w"] > 0, img
    assert page["captions"] == 11
    tables = {t["id"]: t for t in page["tables"]}
    assert tables["table1"]["rows"] == 30 and tables["table2"]["rows"] == 30
    assert tables["table4"]["rows"] == 12 and tables["comparison"]["rows"] == 12
    assert tables["published"]["rows"] == 6
    assert all(t["caption"] for t in page["tables"])
