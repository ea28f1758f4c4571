"""The library's structure, from its sources and its objects (docs/architecture.md):

1. no include runs up the layers: a file of lib/src/LAYER includes headers of its own
   layer, of the layers below it (core < fit < study < report; photo on fit, neither
   including study's or report's headers nor included by them) and the public ones only;
2. no circle of files: the files whose objects call each other's functions (a function
   one object leaves undefined and another defines, read with nm) form no loop.

    check_structure.py SOURCE_DIR BUILD_DIR
"""
import os
import re
import subprocess
import sys
from collections import defaultdict

LAYERS = ["core", "fit", "study", "report", "photo"]
BELOW = {"core": set(), "fit": {"core"}, "study": {"core", "fit"}, "report": {"core", "fit", "study"},
         "photo": {"core", "fit"}}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def layer_of(path, src):
    rel = os.path.relpath(path, src)
    top = rel.split(os.sep)[0]
    return LAYERS.index(top) if top in LAYERS else None


def resolve(name, here, src):
    """The file an include names, searched beside the includer, then in every layer's
    private include folder (the build gives a layer its own and those below it only, so
    an include up the layers fails to compile; this names it), then the public headers;
    None for a generated or system header."""
    for d in [here] + [os.path.join(src, layer) for layer in LAYERS] + [os.path.join(src, "..", "include")]:
        p = os.path.normpath(os.path.join(d, name))
        if os.path.isfile(p):
            return p
    return None


def upward_includes(src):
    bad = []
    for root, _, files in os.walk(src):
        for f in sorted(files):
            if not f.endswith((".c", ".h", ".cc")):
                continue
            path = os.path.join(root, f)
            mine = layer_of(path, src)
            with open(path, encoding="utf-8") as fp:
                for name in INCLUDE.findall(fp.read()):
                    target = resolve(name, root, src)
                    if target is None or mine is None:
                        continue
                    theirs = layer_of(target, src)
                    if theirs is not None and theirs != mine and LAYERS[theirs] not in BELOW[LAYERS[mine]]:
                        bad.append("%s includes %s: %s is not below %s" % (os.path.relpath(path, src), name,
                                                                           LAYERS[theirs], LAYERS[mine]))
    return bad


def symbols(obj):
    out = subprocess.run(["nm", "--defined-only", "-g", obj], capture_output=True, text=True, check=True).stdout
    # Functions only: a table of descriptors (the model registry's families, the export
    # targets) is data that a lower file lists, not a call back into it.
    defined = {line.split()[2] for line in out.splitlines() if len(line.split()) == 3 and line.split()[1] in "TW"}
    out = subprocess.run(["nm", "-u", obj], capture_output=True, text=True, check=True).stdout
    undefined = {line.split()[-1] for line in out.splitlines() if line.strip()}
    return defined, undefined


def circles(build, src):
    """The circles of files calling each other, from the objects of today's sources (an
    object a removed or moved source left in the build folder is not read)."""
    objs = []
    for layer in LAYERS:
        d = os.path.join(build, "lib", "CMakeFiles", "brdfit_%s_objects.dir" % layer)
        for root, _, files in os.walk(d):
            for f in files:
                o = os.path.join(root, f)
                rel = os.path.relpath(o, os.path.join(d, "src"))[:-2]
                if f.endswith(".o") and os.path.isfile(os.path.join(src, rel)):
                    objs.append(o)
    if not objs:
        sys.exit("check_structure.py: no objects under %s/lib (build the library first)" % build)
    name = {o: re.sub(r"^.*_objects\.dir/(src/)?", "", o)[:-2] for o in objs}
    defines, needs = {}, {}
    for o in objs:
        defined, undefined = symbols(o)
        needs[o] = undefined
        for s in defined:
            defines[s] = o
    edges, why = defaultdict(set), defaultdict(set)
    for o in objs:
        for s in needs[o]:
            if s in defines and defines[s] != o:
                edges[o].add(defines[s])
                why[(o, defines[s])].add(s)
    # Tarjan's strongly connected components, iteratively.
    index, low, on, stack, comps, counter = {}, {}, set(), [], [], [0]
    for start in objs:
        if start in index:
            continue
        work = [(start, iter(sorted(edges[start])))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start)
        on.add(start)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(edges[w]))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    ties = ["%s -> %s: %s" % (name[a], name[b], ", ".join(sorted(why[(a, b)])))
                            for a in sorted(comp) for b in sorted(edges[a]) if b in comp]
                    comps.append((sorted(name[c] for c in comp), ties))
    return comps, len(objs)


def main():
    src = os.path.join(sys.argv[1], "lib", "src")
    bad = upward_includes(src)
    comps, n = circles(sys.argv[2], src)
    for b in bad:
        print("up the layers: " + b)
    for files, ties in comps:
        print("circle: " + " <-> ".join(files))
        for t in ties:
            print("  " + t)
    if bad or comps:
        sys.exit(1)
    print("structure: %d objects, no circle; no include up the layers (core < fit < study < report; photo on fit)" % n)


if __name__ == "__main__":
    main()
