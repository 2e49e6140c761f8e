# Copyright 2026 rope_sim_ros contributors
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""
The documentation stays true to the repository: README.md and docs/*.md.

docs/parameters.md is what rope_sim_ros/params/docs.py writes from the parameter table now;
the README stays a front door (at most README_MAX_LINES lines); every relative link names a
file that exists and every #anchor a heading of its page; every repository path and every
rope_sim_ros module the pages name exists (a page naming a module that moved fails here).
"""

from pathlib import Path
import re

import pytest

from rope_sim_ros.params.arrangement import LINE_PARAMETERS_KEY, PARAMETERS_KEY
from rope_sim_ros.params.docs import COMMAND, markdown
from rope_sim_ros.params.table import SPECS

REPO_ROOT = Path(__file__).resolve().parent.parent
README = REPO_ROOT / 'README.md'
DOCS = REPO_ROOT / 'docs'
PARAMETERS_PAGE = DOCS / 'parameters.md'
README_MAX_LINES = 260
PAGES = [README, *sorted(DOCS.glob('*.md'))]

FENCE = re.compile(r'^(```|~~~).*?^\1[ \t]*$', re.MULTILINE | re.DOTALL)
CODE_SPAN = re.compile(r'(`+)(.+?)\1', re.DOTALL)
# [text](target) and ![alt](target), an optional "title" after the target
LINK = re.compile(r'!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+"[^"]*")?\s*\)')
HEADING = re.compile(r'^(#{1,6})[ \t]+(.+?)[ \t]*#*[ \t]*$', re.MULTILINE)
# a path in one of the repository's top-level folders, not the tail of a longer path
REPO_PATH = re.compile(
    r'(?<![\w./-])((?:rope_sim_ros|test|benchmarks|examples|config|launch|bin|docs)'
    r'/[\w./-]*[\w/])')
MODULE = re.compile(r'(?<![\w./-])(rope_sim_ros(?:\.\w+)+)')
# dotted names of ours that are no module: the keys under which a bag stores its parameters
NOT_MODULES = (LINE_PARAMETERS_KEY, PARAMETERS_KEY)


def page_id(page: Path) -> str:
    """Return a page's path in the repository (the test ids)."""
    return str(page.relative_to(REPO_ROOT))


def prose(text: str) -> str:
    """Return a page's text without its code blocks and code spans (links live outside)."""
    return CODE_SPAN.sub('', FENCE.sub('', text))


def slug(heading: str) -> str:
    """Return GitHub's anchor of a heading: lower case, punctuation out, spaces to '-'."""
    text = re.sub(r'\[([^\]]*)\]\([^)]*\)', r'\1', heading)  # a link's text only
    return re.sub(r'[^\w\- ]', '', text.strip().lower()).replace(' ', '-')


def anchors(page: Path) -> set:
    """Return the anchors of a page's headings (a repeated one gets -1, -2, as on GitHub)."""
    found, seen = set(), {}
    for match in HEADING.finditer(FENCE.sub('', page.read_text(encoding='utf-8'))):
        base = slug(match.group(2))
        count = seen.get(base, 0)
        seen[base] = count + 1
        found.add(base if count == 0 else f'{base}-{count}')
    return found


def relative_links(page: Path):
    """Yield (target, anchor) of every relative link of a page (target '' for its own)."""
    for match in LINK.finditer(prose(page.read_text(encoding='utf-8'))):
        target = match.group(1)
        if re.match(r'[a-zA-Z][a-zA-Z0-9+.-]*:', target):  # http:, https:, mailto:
            continue
        path, _, anchor = target.partition('#')
        yield path, anchor


def test_parameters_page_is_generated_from_the_table():
    assert PARAMETERS_PAGE.is_file(), f'docs/parameters.md is missing: run `{COMMAND}`'
    assert PARAMETERS_PAGE.read_text(encoding='utf-8') == markdown(), (
        'docs/parameters.md is not what the parameter table gives now: run '
        f'`{COMMAND}` from the repository root and commit the result')


def test_every_parameter_is_on_the_parameters_page():
    text = PARAMETERS_PAGE.read_text(encoding='utf-8')
    missing = [name for name in SPECS if f'| `{name}` |' not in text]
    assert not missing, f'docs/parameters.md lacks {missing}: run `{COMMAND}`'


def test_readme_is_a_front_door():
    lines = README.read_text(encoding='utf-8').count('\n')
    assert lines <= README_MAX_LINES, (
        f'README.md has {lines} lines, more than {README_MAX_LINES}: move the detail into '
        'a page of docs/ and link it')


@pytest.mark.parametrize('page', PAGES, ids=page_id)
def test_relative_links_point_to_files_that_exist(page):
    broken = [path for path, _ in relative_links(page)
              if path and not (page.parent / path).exists()]
    assert not broken, f'{page_id(page)} links to missing files: {broken}'


@pytest.mark.parametrize('page', PAGES, ids=page_id)
def test_anchors_name_headings(page):
    broken = []
    for path, anchor in relative_links(page):
        target = (page.parent / path) if path else page
        if anchor and target.suffix == '.md' and target.is_file() and \
                anchor not in anchors(target):
            broken.append(f'{path}#{anchor}')
    assert not broken, f'{page_id(page)} links to headings that do not exist: {broken}'


@pytest.mark.parametrize('page', PAGES, ids=page_id)
def test_named_paths_and_modules_exist(page):
    text = page.read_text(encoding='utf-8')
    missing = sorted({path for path in REPO_PATH.findall(text)
                      if not (REPO_ROOT / path).exists()})
    missing += sorted({name for name in MODULE.findall(text)
                       if name not in NOT_MODULES and not module_exists(name)})
    assert not missing, f'{page_id(page)} names what the repository does not hold: {missing}'


def module_exists(dotted: str) -> bool:
    """
    Tell whether a dotted name is a module of ours, or a name inside a module file of ours.

    A package's names must be modules: rope_sim_ros.precompile is not rope_sim_ros's name
    once precompile.py has moved, but rope_sim_ros.params.table.SPECS is table.py's.
    """
    path = REPO_ROOT
    for part in dotted.split('.'):
        if (path / part).is_dir() and (path / part / '__init__.py').is_file():
            path = path / part
        elif (path / f'{part}.py').is_file():
            return True
        else:
            return False
    return True


def test_the_checks_see_what_they_check():
    """The helpers find links, anchors, paths and modules in a page's text as meant."""
    text = ('[a](docs/x.md#two-words) ![b](docs/p.png) [c](https://x.org) `[d](no.md)`\n'
            '```\n[e](in_code.md)\n```\n')
    assert [m.group(1) for m in LINK.finditer(prose(text))] == [
        'docs/x.md#two-words', 'docs/p.png', 'https://x.org']
    assert slug('Two `words`: here & there') == 'two-words-here--there'
    assert REPO_PATH.findall('see `config/berth.yaml`. install/rope_sim_ros/x') == [
        'config/berth.yaml']
    assert module_exists('rope_sim_ros.params.table.SPECS')
    assert module_exists('rope_sim_ros.mooring.precompile')
    assert not module_exists('rope_sim_ros.precompile')
