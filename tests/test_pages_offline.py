"""Every HTML page mechcont writes (``explore``, ``animate --out *.html``) works offline (issue 37, item 3).

The page is parsed as HTML (not searched as text): no element may load anything from the network, nor
anything at all from outside the page: no ``<link>`` (a stylesheet, a font), no ``<script src>``, no
``<iframe>``/``<img>``/``<object>``/``<embed>``/``<source>``/``<audio>``/``<video>`` whose address is not a
``data:`` URI, no ``http(s)://`` or protocol-relative ``//`` address in any ``src``, ``href``, ``action``,
``poster``, ``data`` or ``srcset`` attribute, and no ``@import`` or ``url(...)`` to the network in a
``<style>`` element or ``style`` attribute. A link in prose (text) would be allowed: it loads nothing.
Planar and spatial models, for both kinds of page.
"""

from __future__ import annotations

import re
from html.parser import HTMLParser

import pytest

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.models import load_model
from mechcont.outputs.animation import animate
from mechcont.outputs.explore import explore_page

ADDRESS_ATTRIBUTES = {"src", "href", "xlink:href", "action", "formaction", "poster", "data", "srcset", "background"}
LOADERS = {"script", "img", "iframe", "object", "embed", "source", "audio", "video", "track", "input"}
NETWORK = re.compile(r"^\s*(https?:|ftp:|//)", re.I)
STYLE_NETWORK = re.compile(r"@import|url\(\s*['\"]?\s*(https?:|//)", re.I)


class _Loads(HTMLParser):
    """Everything a page would fetch: ``(tag, attribute, value)``, and its styles' texts."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.fetches: list[tuple[str, str, str]] = []
        self.styles: list[str] = []
        self.tags: set[str] = set()
        self._in_style = False

    def handle_starttag(self, tag, attrs):
        self.tags.add(tag)
        self._in_style = tag == "style"
        for name, value in attrs:
            value = value or ""
            if name == "style":
                self.styles.append(value)
            elif name in ADDRESS_ATTRIBUTES and value and not value.startswith(("#", "data:")) and tag != "a":
                self.fetches.append((tag, name, value))  # a link (<a href>) loads nothing until followed
        if tag == "link":
            self.fetches.append((tag, "link", dict(attrs).get("href") or ""))

    def handle_startendtag(self, tag, attrs):
        self.handle_starttag(tag, attrs)
        self._in_style = False

    def handle_endtag(self, tag):
        if tag == "style":
            self._in_style = False

    def handle_data(self, data):
        if self._in_style:
            self.styles.append(data)


def offline_problems(page: str) -> list[str]:
    """What in the HTML ``page`` loads from the network or from outside the page (empty: none)."""
    p = _Loads()
    p.feed(page)
    p.close()
    out = [f"<{tag} {name}={value!r}>" for tag, name, value in p.fetches
           if tag == "link" or tag in LOADERS or NETWORK.match(value)]
    out += [f"style: {m.group(0)!r}" for text in p.styles for m in [STYLE_NETWORK.search(text)] if m]
    return out


def test_the_check_finds_what_loads_from_outside():
    """The checker itself: each way a page can load from the network is caught, prose and data: URIs are not."""
    bad = ['<link rel="stylesheet" href="https://cdn.example/fa.css">', '<script src="//cdn.example/x.js"></script>',
           '<img src="http://example.com/a.png">', '<svg><image href="https://example.com/a.png"/></svg>',
           '<style>@import "x.css";</style>', '<div style="background:url( \'https://e.x/a.png\')"></div>',
           '<iframe src="page.html"></iframe>', '<script src="player.js"></script>']
    for text in bad:
        assert offline_problems(f"<html><body>{text}</body></html>"), text
    good = ('<p>see <a href="https://example.com">https://example.com</a></p><img src="data:image/png;base64,AAAA">'
            '<svg xmlns="http://www.w3.org/2000/svg"><a href="#x">x</a></svg>'
            '<script>var NS="http://www.w3.org/2000/svg";</script>')
    assert offline_problems(f"<html><body>{good}</body></html>") == []


@pytest.fixture(scope="module")
def branches():
    """A planar branch (the overcentre, F) and a spatial one (the dual-sidestay kinematics, theta), short."""
    over = load_model("overcentre", LU=0.4)
    x0 = find_equilibrium(over, hold={"theta1": 0.3}, free=["F"])
    planar = continuation(over, x0, "F", options=ContinuationOptions(bounds={"F": (-100.0, 120.0)}))
    spatial_model = load_model("dual_sidestay_kinematics")
    x1 = spatial_model.defaults()
    spatial = continuation(spatial_model, x1, "theta",
                           options=ContinuationOptions(bounds={"theta": (0.0, 0.6)}, max_steps=40))
    return {"planar": (over, planar), "spatial": (spatial_model, spatial)}


@pytest.mark.parametrize("kind", ["planar", "spatial"])
def test_the_explorer_page_loads_nothing(branches, kind):
    system, branch = branches[kind]
    page = explore_page(system, [branch])
    assert "<svg" in page or "createElementNS" in page  # the page draws (in its script)
    assert offline_problems(page) == []


@pytest.mark.parametrize("kind", ["planar", "spatial"])
def test_the_animation_page_loads_nothing_and_keeps_its_buttons(branches, kind, tmp_path):
    system, branch = branches[kind]
    out = tmp_path / f"{kind}.html"
    animate(system, branch, out, every=max(1, len(branch) // 6), dpi=30, hold=0.0)
    page = out.read_text(encoding="utf-8")
    assert offline_problems(page) == []
    assert 'class="fa' not in page  # Font Awesome's icons, blank bars offline
    buttons = re.findall(r"<button\b[^>]*>(.*?)</button>", page, re.S)
    assert len(buttons) == 9 and all("<svg" in b and "<path" in b for b in buttons)
