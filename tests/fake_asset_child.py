"""A stand-in for the LOD command line in tests/test_batch.py: behaves by its first
argument like an asset would (ok, a clean failure, a crash, a crash the first time only)
and writes a report shaped like the command line's to the --report path it is given."""
import json, os, sys
args = sys.argv[1:]
report = args[args.index("--report") + 1]
what = args[0]
if what == "crash":
    os.abort()
if what.startswith("sleep:"):  # a long asset: the pid file says it started
    open(what.split(":", 1)[1], "w").write(str(os.getpid()))
    import time
    time.sleep(60)
if what.startswith("flaky:"):
    marker = what.split(":", 1)[1]
    if not os.path.exists(marker):
        open(marker, "w").close()
        os.abort()
ok = what != "bad"
entry = {"input": what, "ok": ok, "error": None if ok else "no mesh objects in bad", "outputs": [], "objects": [], "warnings": [], "seconds": 0.0}
tmp = report + ".tmp"
with open(tmp, "w") as fh:
    json.dump({"files": [entry]}, fh)
os.replace(tmp, report)
