"""Rerun parameters derived from imports (hmfdiff.pipeline.deps): each rule's `library`
digest, checked against the standard library's bytecode-based ModuleFinder and, through
`snakemake -n`, against what really reruns after a library file is edited."""

import modulefinder
import os
import re
import shutil
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from _smoke import ROOT, SMOKE, copy_workflow, job_counts, smoke_workdir, snakemake

from hmfdiff.pipeline.deps import library_files

SCRIPTS = sorted((ROOT / "workflow/scripts").glob("*.py"))


def write(root, rel, text=""):
    path = Path(root, rel)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def test_walk_follows_every_import_form(tmp_path):
    """Absolute, relative (one and two levels), `from package import module`, an import inside
    a function and a chain of imports are followed; attributes, third-party and unreached
    modules are not; the package __init__ files on the way are included."""
    src = tmp_path / "src"
    write(src, "hmfdiff/__init__.py", "__version__ = '0'\n")
    write(src, "hmfdiff/a/__init__.py")
    write(src, "hmfdiff/a/one.py", "from . import two\nfrom .three import value\n")
    write(src, "hmfdiff/a/two.py", "import numpy\n")
    write(src, "hmfdiff/a/three.py", "value = 1\n\ndef f():\n    from ..b import lazy\n")
    write(src, "hmfdiff/b/__init__.py", "from .. import __version__\n")
    write(src, "hmfdiff/b/lazy.py", "import hmfdiff.c.deep\n")
    write(src, "hmfdiff/c/__init__.py")
    write(src, "hmfdiff/c/deep.py", "x = 1\n")
    write(src, "hmfdiff/c/unused.py", "import hmfdiff.a.one\n")
    script = write(tmp_path, "script.py", "import os\nfrom hmfdiff.a.one import two, value\n")
    got = library_files(script, src)
    expected = [
        "hmfdiff/__init__.py",
        "hmfdiff/a/__init__.py",
        "hmfdiff/a/one.py",
        "hmfdiff/a/three.py",
        "hmfdiff/a/two.py",
        "hmfdiff/b/__init__.py",
        "hmfdiff/b/lazy.py",
        "hmfdiff/c/__init__.py",
        "hmfdiff/c/deep.py",
    ]
    assert got == [str(src / p) for p in expected]


def test_relative_import_beyond_the_package_is_refused(tmp_path):
    src = tmp_path / "src"
    write(src, "hmfdiff/__init__.py")
    write(src, "hmfdiff/bad.py", "from ... import x\n")
    script = write(tmp_path, "script.py", "import hmfdiff.bad\n")
    with pytest.raises(ValueError, match="beyond hmfdiff"):
        library_files(script, src)


def test_a_module_edited_after_a_walk_is_read_again(tmp_path):
    """Parsed imports are kept per file version: an edit seen by a later walk in the same
    process (the rules ask for the same modules again and again in one dry run)."""
    src = tmp_path / "src"
    write(src, "hmfdiff/__init__.py")
    one = write(src, "hmfdiff/one.py", "x = 1\n")
    write(src, "hmfdiff/two.py", "y = 2\n")
    script = write(tmp_path, "script.py", "import hmfdiff.one\n")
    assert library_files(script, src) == [str(src / "hmfdiff/__init__.py"), str(one)]
    one.write_text("from . import two\n")
    os.utime(one, ns=(0, 10**9))  # a new version even were the size and clock tick the same
    assert library_files(script, src)[-1] == str(src / "hmfdiff/two.py")


def modulefinder_files(script):
    """The hmfdiff files reached from `script` according to modulefinder (bytecode, stdlib)."""
    finder = modulefinder.ModuleFinder(path=[str(ROOT / "src")])
    finder.run_script(str(script))
    return sorted(
        os.path.relpath(m.__file__, ROOT)
        for name, m in finder.modules.items()
        if name.split(".")[0] == "hmfdiff"
    )


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_library_files_agree_with_modulefinder(script):
    files = [os.path.relpath(f, ROOT) for f in library_files(script, ROOT / "src")]
    assert files == modulefinder_files(script)


def lib(script):
    return {os.path.relpath(f, ROOT / "src/hmfdiff") for f in library_files(script, ROOT / "src")}


def test_hand_known_dependencies():
    s = ROOT / "workflow/scripts"
    assert {"meanfield/fourier.py", "meanfield/orbits.py", "pipeline/io.py"} <= lib(
        s / "equilibrium.py"
    )
    assert {"kinetic/dielectric.py", "kinetic/resonances.py", "meanfield/fourier.py"} <= lib(
        s / "theory.py"
    )
    assert "analysis/fits.py" not in lib(s / "theory.py")
    assert "analysis/fits.py" in lib(s / "fit.py")
    assert "kinetic/theory.py" not in lib(s / "fit.py")
    figure = lib(s / "figure.py")
    assert "analysis/figures/registry.py" in figure and "analysis/figures/style.py" in figure
    assert not any(f.startswith("dynamics/") for f in figure)


def rule_scripts():
    """{rule: script path} from the rule files (`rule name:` ... `script: "../scripts/x.py"`)."""
    found = {}
    for smk in sorted((ROOT / "workflow/rules").glob("*.smk")):
        text = smk.read_text()
        for m in re.finditer(r"^rule (\w+):\n(.*?)(?=^\S|\Z)", text, re.S | re.M):
            s = re.search(r'script:\s*\n\s*"\.\./scripts/([\w.]+)"', m.group(2))
            if s:
                found[m.group(1)] = ROOT / "workflow/scripts" / s.group(1)
    return found


def rule_libraries():
    """{rule: script named by its `library=library("x.py")` parameter} from the rule files."""
    found = {}
    for smk in sorted((ROOT / "workflow/rules").glob("*.smk")):
        text = smk.read_text()
        for m in re.finditer(r"^rule (\w+):\n(.*?)(?=^\S|\Z)", text, re.S | re.M):
            s = re.search(r'^        library=library\("([\w.]+)"\),$', m.group(2), re.M)
            if s:
                found[m.group(1)] = ROOT / "workflow/scripts" / s.group(1)
    return found


def digest_of(files):
    """The digest `library_digest` must give for `files` (paths under ROOT/src), computed
    here: sha256 over each path relative to src and its bytes."""
    import hashlib

    h = hashlib.sha256()
    for f in sorted(files):
        path = ROOT / f
        h.update(path.relative_to(ROOT / "src").as_posix().encode() + b"\0")
        h.update(path.read_bytes() + b"\0")
    return f"{len(files)} files of hmfdiff, sha256 {h.hexdigest()[:16]}"


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_library_digest_covers_exactly_the_modules_the_script_imports(script):
    """The digest a rule carries is over exactly the files modulefinder finds from its script
    (paths and contents, hashed here independently)."""
    from hmfdiff.pipeline.deps import library_digest

    files = modulefinder_files(script)
    assert library_digest(script, ROOT / "src") == digest_of(files)


def test_library_digest_changes_with_any_file_it_covers(tmp_path):
    from hmfdiff.pipeline.deps import library_digest

    src = tmp_path / "src"
    write(src, "hmfdiff/__init__.py")
    one = write(src, "hmfdiff/one.py", "x = 1\n")
    script = write(tmp_path, "script.py", "import hmfdiff.one\n")
    before = library_digest(script, src)
    assert before.startswith("2 files of hmfdiff, sha256 ")
    one.write_text("x = 1\n# a comment\n")
    assert library_digest(script, src) != before
    one.write_text("x = 1\n")
    assert library_digest(script, src) == before  # content, not modification time


def test_every_scripted_rule_carries_its_own_scripts_library_and_no_job_lists_library_files(
    tmp_path,
):
    """Every rule with a script has the parameter `library=library("<its script>")` (editing a
    module its script imports reruns it: Snakemake's params trigger), and in a dry run of the
    whole smoke workflow no job lists a src/hmfdiff file among its inputs (the smoke log showed
    ~25 per job, 1 541 lines in all)."""
    rules, libraries = rule_scripts(), rule_libraries()
    assert libraries == rules
    workdir = copy_workflow(tmp_path)
    r = snakemake(["-n", "--configfile", SMOKE], workdir)
    assert r.returncode == 0, r.stderr[-3000:]
    seen = set()
    for m in re.finditer(r"^(?:local)?rule (\w+):\n((?:    .*\n)+)", r.stdout + r.stderr, re.M):
        rule, block = m.groups()
        inputs = re.search(r"^    input: (.*)$", block, re.M)
        assert not inputs or "src/hmfdiff" not in inputs.group(1), (rule, inputs.group(1))
        seen.add(rule)
    assert set(rules) <= seen, set(rules) - seen


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    return smoke_workdir(tmp_path_factory)


def job_graph(output):
    """[(rule, inputs, outputs)] of every job in a dry run's listing (`localrule all` too)."""
    jobs = []
    for m in re.finditer(r"^(?:local)?rule (\w+):\n((?:    .*\n)+)", output, re.M):
        rule, block = m.groups()
        files = {}
        for key in ("input", "output"):
            f = re.search(rf"^    {key}: (.*)$", block, re.M)
            files[key] = set(f.group(1).split(", ")) if f else set()
        jobs.append((rule, files["input"], files["output"]))
    return jobs


def downstream_jobs(jobs, rules):
    """Indices of the jobs of `rules` and of every job that reads, at any remove, a file one of
    them writes: what editing an input of exactly those rules must rerun."""
    producer = {f: i for i, (_, _, outputs) in enumerate(jobs) for f in outputs}
    readers = {i: set() for i in range(len(jobs))}
    for j, (_, inputs, _) in enumerate(jobs):
        for f in inputs:
            if f in producer:
                readers[producer[f]].add(j)
    todo = [i for i, (rule, _, _) in enumerate(jobs) if rule in rules]
    reached = set(todo)
    while todo:
        for j in readers[todo.pop()] - reached:
            reached.add(j)
            todo.append(j)
    return reached


def downstream_counts(jobs, rules):
    """{rule: count} of `downstream_jobs`."""
    counts = {}
    for i in downstream_jobs(jobs, rules):
        counts[jobs[i][0]] = counts.get(jobs[i][0], 0) + 1
    return counts


def edit_batches(jobs, direct):
    """Modules grouped so that one dry run per group checks each of them: within a group, no
    module's edit reaches the jobs of the rules that import another one directly, so a module
    whose edit reran nothing (or missed its own rules) leaves its direct jobs out of the
    group's plan.  `direct`: {module: set of rules importing it}; greedy, widest first."""
    reach = {m: downstream_jobs(jobs, rules) for m, rules in direct.items()}
    own = {m: {i for i, (r, _, _) in enumerate(jobs) if r in rules} for m, rules in direct.items()}
    batches = []
    for m in sorted(direct, key=lambda m: (-len(reach[m]), m)):
        for batch in batches:
            if all(not own[x] & reach[m] and not own[m] & reach[x] for x in batch):
                batch.append(m)
                break
        else:
            batches.append([m])
    return batches


def test_downstream_counts_follow_files_at_any_remove():
    jobs = [
        ("a", set(), {"x"}),
        ("b", {"x"}, {"y1"}),
        ("b", {"src"}, {"y2"}),
        ("c", {"y1", "z"}, {"w"}),
        ("all", {"w", "y2"}, set()),
    ]
    assert downstream_counts(jobs, {"a"}) == {"a": 1, "b": 1, "c": 1, "all": 1}
    assert downstream_counts(jobs, {"b"}) == {"b": 2, "c": 1, "all": 1}
    assert downstream_counts(jobs, {"c"}) == {"c": 1, "all": 1}


def test_edit_batches_never_hide_one_module_behind_another():
    """A module edited with others must be the only one of its group that reaches its own
    rules' jobs: m_c (rule c) is downstream of m_a (rule a), so they are checked apart; m_d
    (rule d, read by nothing) goes with m_a; m_e (rule c and d) with neither."""
    jobs = [
        ("a", set(), {"x"}),
        ("b", {"x"}, {"y"}),
        ("c", {"y"}, {"w"}),
        ("d", set(), {"v"}),
        ("all", {"w", "v"}, set()),
    ]
    direct = {"m_a": {"a"}, "m_c": {"c"}, "m_d": {"d"}, "m_e": {"c", "d"}}
    batches = edit_batches(jobs, direct)
    assert sorted(map(sorted, batches)) == [["m_a", "m_d"], ["m_c"], ["m_e"]]
    for batch in batches:
        for m in batch:
            others = set().union(*(downstream_jobs(jobs, direct[x]) for x in batch if x != m))
            own = {i for i, (r, _, _) in enumerate(jobs) if r in direct[m]}
            assert not own & others


def test_editing_a_library_module_reruns_exactly_its_dependent_rules(workdir, tmp_path):
    """For src/hmfdiff files that rules' scripts import (as modulefinder sees it), append a
    comment in a copy of the complete smoke run: `snakemake -n` must plan exactly the jobs of
    the importing rules and everything downstream of them (followed file by file through the
    job listing of `snakemake -n --forceall`), then nothing once the files are restored.

    One module is edited per distinct set of importing rules (plus three hand-known ones):
    modules with the same set are the same input of the same jobs, which
    `test_every_job_watches_exactly_the_modules_its_script_imports` checks module by module,
    so editing each of them again would prove nothing more.  Modules are edited together where
    none reaches the jobs of another's rules (`edit_batches`: a module whose edit reran
    nothing leaves its own rules' jobs out of the plan), one dry run per group, in two copies
    of the workdir side by side (one dry run per module took 5 minutes under load)."""
    rules = rule_scripts()
    assert {"equilibrium", "orbits", "theory", "closed_forms", "md", "fit", "validation"} <= set(
        rules
    ) and "figure" in rules
    imports = {rule: modulefinder_files(script) for rule, script in rules.items()}
    known = [
        "src/hmfdiff/meanfield/fourier.py",
        "src/hmfdiff/analysis/fits.py",
        "src/hmfdiff/analysis/figures/registry.py",
    ]
    groups = {}
    for module in known + sorted({f for files in imports.values() for f in files}):
        direct = frozenset(rule for rule, files in imports.items() if module in files)
        groups.setdefault(direct, module)
    assert len(groups) >= 8, groups  # the rules import different library subsets
    direct = {module: set(rules) for rules, module in groups.items()}
    assert set(known) <= set(direct)  # three groups the hand-known checks below pin
    copies = [workdir, tmp_path / "second"]
    shutil.copytree(workdir, copies[1], symlinks=True)  # copy2: the mtimes come along
    r = snakemake(["-n", "--forceall", "--configfile", SMOKE], copies[1])
    assert r.returncode == 0, r.stderr[-3000:]
    jobs = job_graph(r.stdout + r.stderr)
    assert {rule for rule, _, _ in jobs} >= set(rules) | {"all"}
    batches = edit_batches(jobs, direct)
    assert len(batches) < len(direct)  # the point of grouping

    def plans(copy, share):
        """Edit each group of `share` in `copy`, dry-run, restore: {group: job counts}."""
        found = {}
        start = snakemake(["-n", "--configfile", SMOKE], copy)
        found[None] = job_counts(start.stdout + start.stderr)
        for batch in share:
            originals = {m: (copy / m).read_bytes() for m in batch}
            try:
                for m, text in originals.items():
                    (copy / m).write_bytes(text + b"\n# edited by test_deps\n")
                r = snakemake(["-n", "--configfile", SMOKE], copy)
            finally:
                for m, text in originals.items():
                    (copy / m).write_bytes(text)
            assert r.returncode == 0, r.stderr[-3000:]
            found[tuple(batch)] = job_counts(r.stdout + r.stderr)
        end = snakemake(["-n", "--configfile", SMOKE], copy)
        found["restored"] = job_counts(end.stdout + end.stderr)
        return found

    with ThreadPoolExecutor(len(copies)) as pool:
        shares = [batches[i :: len(copies)] for i in range(len(copies))]
        results = list(pool.map(plans, copies, shares))
    for found in results:
        assert found.pop(None) == {}, "the smoke run must be complete to start with"
        assert found.pop("restored") == {}, "restoring the files must rerun nothing"
    planned = {batch: counts for found in results for batch, counts in found.items()}
    assert sorted(planned) == sorted(map(tuple, batches))
    for batch, counts in planned.items():
        rules_hit = set().union(*(direct[m] for m in batch))
        assert counts == downstream_counts(jobs, rules_hit), (batch, rules_hit)
    # hand-known pairs: the expected sets above are not empty or trivially equal
    fourier = downstream_counts(jobs, direct["src/hmfdiff/meanfield/fourier.py"])
    assert {"equilibrium", "orbits", "theory", "closed_forms", "md", "fit", "figure"} <= set(
        fourier
    )
    fits = downstream_counts(jobs, direct["src/hmfdiff/analysis/fits.py"])
    assert {"fit", "validation", "figure"} <= set(fits) and "theory" not in fits
    registry = downstream_counts(jobs, direct["src/hmfdiff/analysis/figures/registry.py"])
    assert set(registry) == {"figure", "all"}
