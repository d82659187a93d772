#!/usr/bin/env python3
"""Checks of `brdffit fit --report` pages for the tool tests (standard
library only).

    check_html.py PAGE [TEXT...]
        PAGE is a well-formed HTML5 document: a doctype, every element
        other than the void ones closed in order, one <title>; it holds
        exactly one image, a PNG data URL that decodes to a PNG of the size
        its width and height attributes say; and every TEXT occurs in the
        page's text (outside tags and attributes).
"""
import base64
import html.parser
import struct
import sys

VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta",
        "source", "track", "wbr"}


def fail(msg):
    sys.stderr.write("check_html: %s\n" % msg)
    sys.exit(1)


class Checker(html.parser.HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.stack, self.images, self.text, self.titles, self.doctype = [], [], [], 0, False

    def handle_decl(self, decl):
        self.doctype = decl.lower() == "doctype html"

    def handle_starttag(self, tag, attrs):
        if tag == "img":
            self.images.append(dict(attrs))
        if tag == "title":
            self.titles += 1
        if tag not in VOID:
            self.stack.append((tag, self.getpos()))

    def handle_startendtag(self, tag, attrs):
        fail("self-closing <%s/> at %s" % (tag, self.getpos()))

    def handle_endtag(self, tag):
        if tag in VOID:
            fail("end tag of the void element %s at %s" % (tag, self.getpos()))
        if not self.stack or self.stack[-1][0] != tag:
            fail("</%s> at %s closes %s" % (tag, self.getpos(),
                                            self.stack[-1] if self.stack else "nothing"))
        self.stack.pop()

    def handle_data(self, data):
        self.text.append(data)


def main(argv):
    if len(argv) < 2:
        fail("usage: check_html.py PAGE [TEXT...]")
    with open(argv[1], encoding="utf-8") as f:
        page = f.read()
    c = Checker()
    c.feed(page)
    c.close()
    if not c.doctype:
        fail("no <!DOCTYPE html>")
    if c.stack:
        fail("unclosed elements: %s" % c.stack)
    if c.titles != 1:
        fail("%d <title> elements" % c.titles)
    if len(c.images) != 1:
        fail("%d images, expected 1" % len(c.images))
    img = c.images[0]
    prefix = "data:image/png;base64,"
    if not img.get("src", "").startswith(prefix) or not img.get("alt"):
        fail("the image is not a PNG data URL with alt text")
    png = base64.b64decode(img["src"][len(prefix):], validate=True)
    if png[:8] != b"\x89PNG\r\n\x1a\n" or png[12:16] != b"IHDR":
        fail("the data URL is not a PNG")
    w, h = struct.unpack(">II", png[16:24])
    if (str(w), str(h)) != (img.get("width"), img.get("height")):
        fail("the PNG is %d x %d, the attributes say %s x %s" % (w, h, img.get("width"),
                                                                 img.get("height")))
    text = " ".join(c.text)
    for want in argv[2:]:
        if want not in text:
            fail("no %r in the page's text" % want)
    print("ok: %d x %d picture, %d bytes" % (w, h, len(page)))


main(sys.argv)
