#!/usr/bin/env python3
"""Checks that the documentation holds together (ctest label `docs`, so .ci/test runs it):
- every relative link in every tracked Markdown file resolves to a file, and its #anchor to a heading there;
- every citation of a document section in the code, written `<path>.md "Heading"` (more headings may follow,
  `<path>.md "A", "B"`; a heading "Title: more" or "Title (more)" may be cited as "Title"), names a document that exists and headings it has;
- no code comment cites the README by section any more (`README "..."`): sections live beside the code;
- the top-level README stays a user guide: at most 400 lines.
Usage: check_docs.py REPO_ROOT. Prints one line per problem and exits 1 if there is any."""
import os
import re
import subprocess
import sys

CODE_EXTS = ('.cpp', '.h', '.glsl', '.comp', '.py', '.cmake', '.txt', '.sh', '.md')
README_LINES_MAX = 400


def anchor(heading):
    """GitHub's anchor for a heading: lowercase, punctuation dropped, spaces to hyphens."""
    text = re.sub(r'[^\w\- ]', '', heading.strip().lower())
    return text.replace(' ', '-')


def headings(path, cache={}):
    """(heading texts, anchors) of a Markdown file, fenced code blocks skipped."""
    if path not in cache:
        texts, anchors, fenced = set(), set(), False
        for line in open(path, encoding='utf-8'):
            if line.startswith('```'):
                fenced = not fenced
            elif not fenced and re.match(r'#{1,6} ', line):
                text = line.lstrip('#').strip()
                texts.add(text)
                texts.add(text.replace('`', ''))
                base, n = anchor(text), 0
                while (base if n == 0 else f'{base}-{n}') in anchors:
                    n += 1
                anchors.add(base if n == 0 else f'{base}-{n}')
        cache[path] = (texts, anchors)
    return cache[path]


def check_links(root, md, problems):
    text = open(os.path.join(root, md), encoding='utf-8').read()
    text = re.sub(r'```.*?```', '', text, flags=re.S)
    text = re.sub(r'`[^`\n]*`', '', text)
    for target in re.findall(r'\]\(([^)\s]+)\)', text):
        if re.match(r'[a-z]+:', target):
            continue  # http(s), mailto: outside the tree
        path, _, frag = target.partition('#')
        full = os.path.normpath(os.path.join(root, os.path.dirname(md), path)) if path else os.path.join(root, md)
        if not os.path.exists(full):
            problems.append(f'{md}: link to {target}: no such file')
        elif frag and full.endswith('.md') and frag not in headings(full)[1]:
            problems.append(f'{md}: link to {target}: no heading with anchor #{frag}')


CITATION = re.compile(r'([\w./-]+\.md)((?:,? "[^"\n]+")+)')


def check_citations(root, path, problems):
    try:
        text = open(os.path.join(root, path), encoding='utf-8').read()
    except UnicodeDecodeError:
        return
    for n, line in enumerate(text.splitlines(), 1):
        if re.search(r'README "', line) and not path.endswith('check_docs.py'):
            problems.append(f'{path}:{n}: cites the README by section; cite the document beside the code instead')
        for doc, names in CITATION.findall(line):
            full = os.path.normpath(os.path.join(root, doc))
            if not os.path.exists(full):
                full = os.path.normpath(os.path.join(root, os.path.dirname(path), doc))
            if not os.path.exists(full):
                problems.append(f'{path}:{n}: cites {doc}, which does not exist')
                continue
            for name in re.findall(r'"([^"\n]+)"', names):
                texts = headings(full)[0]
                if name not in texts and not any(t.startswith((name + ':', name + ' (')) for t in texts):
                    problems.append(f'{path}:{n}: cites {doc} "{name}", which has no such heading')


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else '.')
    files = subprocess.run(['git', '-C', root, 'ls-files', '--cached', '--others', '--exclude-standard'],
                           capture_output=True, text=True, check=True).stdout.split()
    files = [f for f in files if os.path.isfile(os.path.join(root, f))]
    problems = []
    for f in files:
        if f.endswith('.md'):
            check_links(root, f, problems)
        if f.endswith(CODE_EXTS):
            check_citations(root, f, problems)
    lines = sum(1 for _ in open(os.path.join(root, 'README.md'), encoding='utf-8'))
    if lines > README_LINES_MAX:
        problems.append(f'README.md: {lines} lines, more than {README_LINES_MAX}: it is a user guide; move the '
                        'rest beside the code it describes')
    for p in problems:
        print(p)
    print(f'check_docs: {len(files)} files, {len(problems)} problems')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
