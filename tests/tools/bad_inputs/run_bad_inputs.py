#!/usr/bin/env python3
"""Throws a few hundred bad inputs at the five executables (issue 17's trial, in spirit).

Every case runs one command in a fresh folder holding clean fixtures (a model file, a small
measurement file, the tool's base config) with a time limit, and checks:
  * the exit status is neither 0 nor a signal (1 or 2; a timeout is a failure: a hang),
  * stderr is exactly one line (the tools run with -q) and names the file, field or row the
    case is about (each case lists the words one of which must appear),
  * no file of the folder was created, modified or removed (inputs intact, no partial outputs,
    no temporary or staging files left),
and, before the cases, that every base config succeeds (so a case fails because of its one change).

Usage: run_bad_inputs.py BIN_DIR [--only SUBSTRING] [--list] [--keep DIR] [--timeout S]
"""
import argparse
import hashlib
import json
import math
import os
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
BINDIR = ""  # the executables' folder (main sets it; a check that runs a second command needs it)

MODEL = {"drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5, "x^9": -3.1, "y": -0.1},
         "diffusion": {"1": 0.02, "x^2": 0.01}}
OTHER_MODEL = {"drift": {"x": -1.0, "x^3": -1.0, "y": -0.2}, "diffusion": {"1": 0.05}}
# the top-level keys fpk-stationary's output and simulate-vehs's statistics always carry
# (docs/outputs.md): vehs-compare tells the two apart by them
FPK_KEYS = {"E[X^2]": 0.1, "E[Y^2]": 0.2, "E[XY]": 0.0, "boundary_mass": 0.0, "solve": {"solver": "direct"}}
MC_KEYS = {"E[X^2]": 0.7, "E[Y^2]": 0.2, "E[XY]": 0.0, "stderr": {}, "simulation": {"scheme": "paper"}}

BASE = {
    "simulate-vehs": {"model": "model.json", "trajectories": 2, "duration": 5, "dt": 0.01,
                      "output": "sim.csv"},
    "identify-vehs": {"data": ["data.csv"], "output": "learned.json"},
    "fpk-stationary": {"model": "model.json", "grid": {"x": 250, "y": 250}, "output": "fpk.json"},
    "diagnose-vehs": {"model": "model.json", "data": ["data.csv"], "output": "diag.json", "replicates": 0,
                      "suspects": False},
    "vehs-compare": {"learned": "model.json", "truth": "model.json", "output": "cmp.csv"},
}
TOOLS = list(BASE)


class Case:
    """One command. expect: "error" (the default: one-line error, nothing written), "ok" (status 0)
    or a signal sent after `signal_after` s (status 128 + signal, nothing written); a
    `check(folder, stdout, stderr)` returns further problems (with "error": before the folder goes)."""
    def __init__(self, name, tool, config=None, raw=None, args=(), files=None, mentions=(), setup=None,
                 config_name="cfg.json", expect="error", check=None, signal_after=1.0, owner="", close_stdout=False):
        self.name, self.tool, self.config, self.raw = name, tool, config, raw
        self.args, self.files, self.mentions, self.setup = list(args), files or {}, list(mentions), setup
        self.config_name, self.expect, self.check, self.signal_after = config_name, expect, check, signal_after
        self.owner = owner  # a case another open issue fixes: its failure is listed, not counted
        self.close_stdout = close_stdout  # the reader of stdout goes away at once (tool ... | head -1)


def with_(tool, **changes):
    c = json.loads(json.dumps(BASE[tool]))
    for k, v in changes.items():
        if v is DELETE:
            c.pop(k, None)
        else:
            c[k] = v
    return c


DELETE = object()


def deep(n, leaf="1"):
    return "[" * n + leaf + "]" * n


def csv_text(rows, header="traj,t,x"):
    return header + "\n" + "".join(",".join(str(v) for v in r) + "\n" for r in rows)


def cases():
    out = []
    add = out.append
    # ---- every tool: the config file itself -----------------------------------------------
    for t in TOOLS:
        add(Case("missing config", t, args=["nope.json"], config_name=None, mentions=["nope.json"]))
        add(Case("config is a directory", t, args=["adir"], config_name=None, mentions=["adir"],
                 setup=lambda d: os.mkdir(os.path.join(d, "adir"))))
        add(Case("empty config", t, raw="", mentions=["cfg.json"]))
        add(Case("config is a FIFO without writer", t, args=["cfgfifo"], config_name=None, mentions=["cfgfifo"],
                 setup=lambda d: os.mkfifo(os.path.join(d, "cfgfifo"))))
        add(Case("config is /dev/zero", t, args=["/dev/zero"], config_name=None, mentions=["/dev/zero"]))
        add(Case("model is /dev/zero", t, with_(t, **{list(BASE[t])[0]: "/dev/zero"}), mentions=["/dev/zero"]))
        add(Case("config not JSON", t, raw="{model: x}", mentions=["cfg.json"]))
        add(Case("trailing garbage", t, raw=json.dumps(BASE[t]) + " xyz", mentions=["cfg.json"]))
        add(Case("two documents", t, raw=json.dumps(BASE[t]) + json.dumps(BASE[t]), mentions=["cfg.json"]))
        add(Case("config is a list", t, raw="[1, 2]", mentions=["cfg.json"]))
        add(Case("config is a number", t, raw="3", mentions=["cfg.json"]))
        add(Case("nested 100000 deep in a key of wrong type", t,
                 raw=json.dumps(BASE[t])[:-1] + ', "' + list(BASE[t])[0] + '_x": ' + deep(100000) + "}",
                 mentions=["cfg.json"]))
        first = list(BASE[t])[0]
        add(Case("nested 100000 deep as a value", t,
                 raw='{"' + first + '": ' + deep(100000) + "}", mentions=["cfg.json"]))
        add(Case("nested 65 deep", t, raw='{"' + first + '": ' + deep(65) + "}", mentions=["cfg.json"]))
        add(Case("unknown key", t, with_(t, outptu="x.json"), mentions=["outptu"]))
        add(Case("NUL after the config", t, raw=json.dumps(BASE[t]) + "\x00garbage", mentions=["cfg.json"]))
        add(Case("NUL in config", t, raw=json.dumps(BASE[t])[:-1] + "\x00}", mentions=["cfg.json"]))
        add(Case("huge number", t, raw=json.dumps(BASE[t])[:-1] + ', "seed": 1e400}', mentions=["cfg.json"]))
        # wrong types for every key of the base config
        for key in BASE[t]:
            for bad in ({}, [], True, None, -1, "", "text", deep(50, "0")):
                v = json.loads(bad) if isinstance(bad, str) and bad.startswith("[") else bad
                base = BASE[t][key]
                if isinstance(base, bool) and isinstance(v, bool):
                    continue
                if v == {} and (isinstance(base, dict) or key == "suspects"):
                    continue  # an object of optional keys may be empty
                if isinstance(base, str) and isinstance(v, str) and v != "":
                    continue  # another name: a missing file, covered below
                if isinstance(base, (int, float)) and not isinstance(base, bool) and v == "text":
                    pass
                if v == -1 and not isinstance(base, (int, float)):
                    continue
                add(Case(f"{key} = {json.dumps(v)[:20]}", t, with_(t, **{key: v}), mentions=[key, "cfg.json"]))
        # --threads, --set
        for th in ("-1", "abc", "100000", "1e3", ""):
            add(Case(f"--threads {th!r}", t, BASE[t], args=["--threads", th], mentions=["threads"]))
        add(Case("--set unknown key", t, BASE[t], args=["--set", "nokey=1"], mentions=["nokey"]))
        add(Case("--set deep value", t, BASE[t], args=["--set", first + "=" + deep(30000)], mentions=[first]))
        add(Case("--set broken list", t, BASE[t], args=["--set", first + "=[1,2"], mentions=[first]))
        add(Case("unknown option", t, BASE[t], args=["--frobnicate"], mentions=["frobnicate"]))

    # ---- outputs that must never be written --------------------------------------------------
    outputs = {"simulate-vehs": ["output", "summary"], "identify-vehs": ["output"], "fpk-stationary": ["output", "density"],
               "diagnose-vehs": ["output", "history"], "vehs-compare": ["output"]}
    inputs = {"simulate-vehs": ["model.json"], "identify-vehs": ["data.csv"], "fpk-stationary": ["model.json"],
              "diagnose-vehs": ["model.json", "data.csv"], "vehs-compare": ["model.json"]}
    for t, keys in outputs.items():
        for key in keys:
            for inp in inputs[t] + ["cfg.json"]:
                add(Case(f"{key} = input {inp}", t, with_(t, **{key: inp}), mentions=[inp]))
            add(Case(f"{key} = ./ input", t, with_(t, **{key: "./" + inputs[t][0]}), mentions=[inputs[t][0]]))
            add(Case(f"{key} = hard link of an input", t, with_(t, **{key: "hard.json"}), mentions=["hard.json"],
                     setup=lambda d, i=inputs[t][0]: os.link(os.path.join(d, i), os.path.join(d, "hard.json"))))
            add(Case(f"{key} = symlink to an input", t, with_(t, **{key: "link.json"}), mentions=["link.json"],
                     setup=lambda d, i=inputs[t][0]: os.symlink(i, os.path.join(d, "link.json"))))
            add(Case(f"{key} = symlink to /dev/null", t, with_(t, **{key: "null.json"}), mentions=["null.json"],
                     setup=lambda d: os.symlink("/dev/null", os.path.join(d, "null.json"))))
            add(Case(f"{key} = dangling symlink", t, with_(t, **{key: "dangling.json"}), mentions=["dangling.json"],
                     setup=lambda d: os.symlink("nowhere/x.json", os.path.join(d, "dangling.json"))))
            add(Case(f"{key} = a directory", t, with_(t, **{key: "outdir"}), mentions=["outdir"],
                     setup=lambda d: os.mkdir(os.path.join(d, "outdir"))))
            add(Case(f"{key} = 300-byte name", t, with_(t, **{key: "o" * 300 + ".json"}), mentions=["longer"]))
            add(Case(f"{key} = a FIFO", t, with_(t, **{key: "fifo"}), mentions=["fifo"],
                     setup=lambda d: os.mkfifo(os.path.join(d, "fifo"))))
            add(Case(f"{key} under a file", t, with_(t, **{key: "data.csv/x.json"}), mentions=["data.csv"]))
            add(Case(f"{key} empty", t, with_(t, **{key: ""}), mentions=[key]))
            add(Case(f"{key} = /dev/null", t, with_(t, **{key: "/dev/null"}), mentions=["/dev/null"]))
            add(Case(f"{key} with a NUL inside", t, with_(t, **{key: "out.npy\u0000.csv"}), mentions=[f"'{key}'"]))
        if len(keys) > 1:
            add(Case(f"{keys[0]} = {keys[1]}", t, with_(t, **{keys[0]: "same.json", keys[1]: "same.json"}),
                     mentions=["same.json"]))
    # (as root a mode of 555 does not stop writes: /proc refuses new files to everyone)
    add(Case("diagnose output in an unwritable folder (report and history elsewhere)", "diagnose-vehs",
             with_("diagnose-vehs", output="/proc/vehs_diag.json", report="rep"), mentions=["/proc"]))
    add(Case("fpk output in an unwritable folder (figures elsewhere)", "fpk-stationary",
             with_("fpk-stationary", output="/proc/vehs_fpk.json", density="fpk.density.csv", figures="figs"),
             mentions=["/proc"]))
    add(Case("identify: data listed twice", "identify-vehs", with_("identify-vehs", data=["data.csv", "data.csv"]),
             mentions=["data.csv"]))
    add(Case("identify: data listed twice via ./", "identify-vehs", with_("identify-vehs", data=["data.csv", "./data.csv"]),
             mentions=["data.csv"]))
    add(Case("diagnose: data listed twice", "diagnose-vehs", with_("diagnose-vehs", data=["data.csv", "data.csv"]),
             mentions=["data.csv"]))
    add(Case("report folder is a file", "diagnose-vehs", with_("diagnose-vehs", report="data.csv"), mentions=["data.csv"]))
    add(Case("figures folder is a file", "fpk-stationary", with_("fpk-stationary", figures="model.json"),
             mentions=["model.json"]))

    # ---- model files ----------------------------------------------------------------------
    bad_models = {
        "model not JSON": "{drift: 1}",
        "model trailing garbage": json.dumps(MODEL) + "x",
        "model nested deep": '{"drift": ' + deep(100000) + "}",
        "model bad term": json.dumps({"drift": {"x^^2": 1}, "diffusion": {"1": 0.1}}),
        "model negative diffusion": json.dumps({"drift": {"x": -1, "y": -0.1}, "diffusion": {"1": -0.1}}),
        "model no diffusion": json.dumps({"drift": {"x": -1, "y": -0.1}}),
        "model NaN coefficient": '{"drift": {"x": NaN, "y": -0.1}, "diffusion": {"1": 0.1}}',
        "model coefficient a string": json.dumps({"drift": {"x": "1", "y": -0.1}, "diffusion": {"1": 0.1}}),
        "model is a list": "[]",
        "model empty": "",
        "model huge exponent term": json.dumps({"drift": {"x^100000": 1, "y": -0.1}, "diffusion": {"1": 0.1}}),
    }
    for t, key in (("simulate-vehs", "model"), ("fpk-stationary", "model"), ("diagnose-vehs", "model"),
                   ("vehs-compare", "learned")):
        for name, text in bad_models.items():
            add(Case(f"{name}", t, with_(t, **{key: "bad_model.json"}), files={"bad_model.json": text},
                     mentions=["bad_model.json"]))
        add(Case("model is a directory", t, with_(t, **{key: "mdir"}), mentions=["mdir"],
                 setup=lambda d: os.mkdir(os.path.join(d, "mdir"))))
        add(Case("model is missing", t, with_(t, **{key: "missing.json"}), mentions=["missing.json"]))
        add(Case("model path with a NUL inside", t, with_(t, **{key: "model.json\u0000x"}), mentions=[f"'{key}'"]))

    # ---- measurement files ----------------------------------------------------------------
    bad_data = {
        "data empty": "",
        "data header only": "traj,t,x\n",
        "data one row": csv_text([(0, 0.0, 0.1)]),
        "data text in a number": csv_text([(0, 0.0, 0.1), (0, 0.01, "abc"), (0, 0.02, 0.2)]),
        "data NaN": csv_text([(0, 0.0, 0.1), (0, 0.01, "nan"), (0, 0.02, 0.2)]),
        "data inf": csv_text([(0, 0.0, 0.1), (0, 0.01, "inf"), (0, 0.02, 0.2)]),
        "data time going back": csv_text([(0, 0.0, 0.1), (0, 0.02, 0.2), (0, 0.01, 0.3)] * 5),
        "data no x column": "traj,t,y\n0,0,1\n0,0.01,2\n",
        "data binary garbage": "\x00\x01\x02\xff" * 100,
        "data missing field": "traj,t,x\n0,0.0,0.1\n0,0.01\n0,0.02,0.2\n",
        "data CR-only line ends": csv_text([(0, 0.01 * i, 0.1 * ((i * 7) % 13 - 6)) for i in range(30)]).replace("\n", "\r"),
        "data extra field": csv_text([(0, 0.01 * i, 0.1 * ((i * 7) % 13 - 6)) for i in range(30)]).replace(
            "\n0,0.1,", "\n0,0.1,7,", 1),
        "data npy garbage": "\x93NUMPY\x01\x00\xff\xff{'descr': '<f8', 'fortran_order': False, 'shape': (99999999999,), }",
    }
    bad_data["data NUL inside a value (shown escaped)"] = csv_text(
        [(0, 0.01 * i, 0.1 * ((i * 7) % 13 - 6)) for i in range(30)]).replace("\n0,0.1,", "\n0,0.1,0.25\x00", 1)
    for t in ("identify-vehs", "diagnose-vehs"):
        for name, text in bad_data.items():
            fname = "bad.npy" if "npy" in name else "bad.csv"
            add(Case(name, t, with_(t, data=[fname]), files={fname: text},
                     mentions=["'0.25\\x00" if "NUL inside" in name else fname]))
        add(Case("data is a NumPy .npz archive", t, with_(t, data=["arrays.npz"]), files={"arrays.npz": "PK\x03\x04" * 50},
                 mentions=["arrays.npz"]))
        add(Case("data is a directory", t, with_(t, data=["ddir"]), mentions=["ddir"],
                 setup=lambda d: os.mkdir(os.path.join(d, "ddir"))))
        add(Case("data is missing", t, with_(t, data=["missing.csv"]), mentions=["missing.csv"]))
        add(Case("data empty list", t, with_(t, data=[]), mentions=["data"]))
        add(Case("duplicate column x", t, with_(t, data=["dup.csv"]), mentions=["dup.csv"],
                 setup=lambda d: make_duplicate_column(d, "data.csv", "dup.csv")))
        add(Case("UTF-8 BOM before the header is read as the header", t, with_(t, data=["bom.csv"]), expect="ok",
                 check=lambda d, out, err: [],
                 setup=lambda d: make_bom(d, "data.csv", "bom.csv")))
        add(Case("glitch sample", t, with_(t, data=["glitch.csv"]), mentions=["glitch.csv"],
                 setup=lambda d: make_glitch(d, "data.csv", "glitch.csv")))
        add(Case("a truncated last line (x '0.')", t, with_(t, data=["cut.csv"]), mentions=["cut.csv: line"],
                 setup=lambda d: make_truncated_end(d, "data.csv", "cut.csv")))
        add(Case("a 0 logged at a record's first sample", t, with_(t, data=["start0.csv"]),
                 mentions=["start0.csv: line"], setup=lambda d: make_zero_start(d, "data.csv", "start0.csv")))
        # what the readers accepted silently or answered badly (issue 36)
        add(Case(".mat record ids 0.2 and 0.7 (not integers)", t, with_(t, data=["ids.mat"]),
                 mentions=["ids.mat: row 1: record id 0.2 is not an integer"], setup=make_fractional_id_mat))
        add(Case("record id 2^53 + 1", t, with_(t, data=["bigid.csv"]), mentions=["2^53 - 1 = 9007199254740991"],
                 setup=lambda d: make_big_ids(d, "data.csv", "bigid.csv", 2 ** 53 + 1)))
        add(Case(".npy field of shape (2,)", t, with_(t, data=["sub.npy"]), mentions=["sub.npy: field 'x' is a sub-array"],
                 setup=make_subarray_npy))
        add(Case("a corrupt v7.3 .mat file", t, with_(t, data=["bad73.mat"]), mentions=["bad73.mat: cannot read"],
                 setup=make_corrupt_mat73))
        add(Case("data is a FIFO without writer", t, with_(t, data=["fifo.csv"]), mentions=["fifo.csv: is a FIFO"],
                 setup=lambda d: os.mkfifo(os.path.join(d, "fifo.csv"))))
        add(Case("data is a socket", t, with_(t, data=["sock.csv"]), mentions=["sock.csv: is a socket"],
                 setup=make_socket))
        add(Case("NUL inside the data path", t, with_(t, data=["data.csv\u0000junk"]), mentions=["'data'"]))
        add(Case("a line feed inside the data path (a file of that name exists)", t, with_(t, data=["data\n.csv"]),
                 mentions=["'data'"], setup=lambda d: shutil.copy(os.path.join(d, "data.csv"), os.path.join(d, "data\n.csv"))))
        if t == "identify-vehs":
            add(Case("x with a large offset (names the cure, detrend)", t, with_(t, data=["offset.csv"]),
                     mentions=["detrend"], setup=lambda d: make_offset(d, "data.csv", "offset.csv")))
        add(Case("a dropout logged as 0 (a flat stretch)", t, with_(t, data=["dropout.csv"]), mentions=["dropout.csv"],
                 setup=lambda d: make_dropout(d, "data.csv", "dropout.csv")))
        add(Case("a record sampled at another interval in the same file", t, with_(t, data=["mixed.csv"]),
                 mentions=["mixed.csv"], files={"mixed.csv": csv_text(
                     [(0, 0.01 * i, 0.1 * ((i * 7) % 13 - 6)) for i in range(40)] +
                     [(1, 0.02 * i, 0.1 * ((i * 5) % 11 - 5)) for i in range(40)])}))
        add(Case("the sampling interval halves inside a record", t, with_(t, data=["halved.csv"]),
                 mentions=["halved.csv: line 42 (record traj=0): the sampling interval changes from 0.01 to 0.005"],
                 files={"halved.csv": csv_text([(0, round(0.01 * min(i, 39) + 0.005 * max(i - 39, 0), 4),
                                                 0.1 * ((i * 7) % 13 - 6)) for i in range(80)])}))
        add(Case("columns t and x name one column", t, with_(t, columns={"t": "x", "x": "x"}),
                 mentions=["'columns.t' and 'columns.x' name the same column 'x'"]))
        add(Case("columns t names x's default column", t, with_(t, columns={"t": "x"}),
                 mentions=["'columns.t' names the column 'x', which is x's by default"]))
        add(Case("config key given twice", t, raw=json.dumps(BASE[t])[:-1] + ', "output": "other.json"}',
                 mentions=["output"]))

    # ---- values that would be ignored, contradicted or out of range -------------------------
    add(Case("keep_terms outside the library", "identify-vehs", with_("identify-vehs", keep_terms=["x^20"]),
             mentions=["keep_terms"]))
    add(Case("dt contradicting the time column", "identify-vehs", with_("identify-vehs", dt=0.5), mentions=["dt"]))
    add(Case("se_block longer than the data allow", "identify-vehs", with_("identify-vehs", se_block=10000000),
             mentions=["se_block = 10000000 is outside"]))
    add(Case("se_block shorter than a feature block", "identify-vehs", with_("identify-vehs", se_block=1),
             mentions=["se_block = 1 is outside"]))
    add(Case("se_block within range: the model file states the batches used", "identify-vehs",
             with_("identify-vehs", se_block=512), expect="ok", check=check_stderr_method))
    add(Case("stlsq_threshold without stlsq", "identify-vehs", with_("identify-vehs", stlsq_threshold=0.1),
             mentions=["stlsq_threshold"]))
    add(Case("ssr_rule with sparsity none", "identify-vehs", with_("identify-vehs", sparsity="none", ssr_rule="abs_coef"),
             mentions=["ssr_rule"]))
    add(Case("fpk: sor settings with the direct solver", "fpk-stationary", with_("fpk-stationary", sor={"alpha": 0.5}),
             mentions=["sor"]))
    add(Case("fpk: iterative settings with the direct solver", "fpk-stationary",
             with_("fpk-stationary", iterative={"tolerance": 1e-8}), mentions=["iterative"]))
    add(Case("folds beyond the data", "identify-vehs", with_("identify-vehs", folds=100000), mentions=["folds"]))
    add(Case("statistics.batches beyond the samples", "simulate-vehs",
             with_("simulate-vehs", statistics={"output": "st.json", "batches": 100000}), mentions=["batches"]))
    add(Case("fpk auto_domain_efolds 1000", "fpk-stationary",
             with_("fpk-stationary", auto_domain_efolds=1000), mentions=["auto_domain_efolds"]))
    add(Case("fpk grid 7000^2 (inside the cell limit) beyond the memory limit", "fpk-stationary",
             with_("fpk-stationary", grid={"x": 7000, "y": 7000}), mentions=["memory", "grid"]))
    add(Case("fpk grid 1e9 cells", "fpk-stationary", with_("fpk-stationary", grid={"x": 100000, "y": 100000}),
             mentions=["grid"]))
    add(Case("fpk sor at 300^2 with 1e9 sweeps", "fpk-stationary",
             with_("fpk-stationary", grid={"x": 300, "y": 300}, solver="sor", sor={"max_iterations": 1000000000}),
             mentions=["sor", "max_iterations"]))
    add(Case("fpk sor at 300^2 with the defaults", "fpk-stationary",
             with_("fpk-stationary", grid={"x": 300, "y": 300}, solver="sor"), mentions=["max_iterations"]))
    add(Case("fpk sweep all points failing", "fpk-stationary",
             with_("fpk-stationary", sweep={"2D": [-0.03, -0.01, 3]}), mentions=["sweep", "2D"]))
    add(Case("compare: fpk of another model", "vehs-compare", with_("vehs-compare", fpk="fpk_other.json"),
             files={"fpk_other.json": json.dumps(dict(FPK_KEYS, model=OTHER_MODEL))},
             mentions=["fpk_other.json"]))
    add(Case("compare: fpk without a model", "vehs-compare", with_("vehs-compare", fpk="fpk_nomodel.json"),
             files={"fpk_nomodel.json": json.dumps(FPK_KEYS)},
             mentions=["fpk_nomodel.json"]))
    # every input's kind is checked before anything is printed (a model given as 'fpk' printed the
    # whole parameter table, then failed; fpk-stationary's output given as 'monte_carlo' was
    # printed as "Monte Carlo 0.89 (no standard error)" with exit 0)
    add(Case("compare: a model file as fpk", "vehs-compare", with_("vehs-compare", fpk="model.json"),
             mentions=["'fpk' names model.json, a model file"],
             check=lambda d, out, err: ["printed to stdout before failing"] if out.strip() else []))
    add(Case("compare: fpk-stationary's output as monte_carlo", "vehs-compare",
             with_("vehs-compare", monte_carlo="fpk.json"), files={"fpk.json": json.dumps(dict(FPK_KEYS, model=MODEL))},
             mentions=["'monte_carlo' names fpk.json, fpk-stationary's output"],
             check=lambda d, out, err: ["printed to stdout before failing"] if out.strip() else []))
    add(Case("compare: fpk-stationary's output as learned", "vehs-compare",
             with_("vehs-compare", learned="fpk.json"), files={"fpk.json": json.dumps(dict(FPK_KEYS, model=MODEL))},
             mentions=["'learned' names fpk.json, fpk-stationary's output; it takes a model file"]))
    add(Case("compare: Monte Carlo statistics as fpk", "vehs-compare",
             with_("vehs-compare", fpk="mc.json"), files={"mc.json": json.dumps(dict(MC_KEYS, model=MODEL))},
             mentions=["'fpk' names mc.json, simulate-vehs's Monte Carlo statistics"]))
    add(Case("compare: statistics with null stderr and null value", "vehs-compare",
             with_("vehs-compare", monte_carlo="mc.json"),
             files={"mc.json": json.dumps(dict(MC_KEYS, **{"E[X^2]": None}, model=MODEL))},
             mentions=["mc.json"]))
    for t in ("simulate-vehs",):
        add(Case("trajectories 1e12", t, with_(t, trajectories=10 ** 12), mentions=["trajectories", "memory"]))
        add(Case("duration 1e12", t, with_(t, duration=1e12), mentions=["duration", "memory", "samples"]))
        add(Case("dt 0", t, with_(t, dt=0), mentions=["dt"]))
        add(Case("dt negative", t, with_(t, dt=-0.01), mentions=["dt"]))
    add(Case("simulate: a .mat output name (CSV text under a binary name)", "simulate-vehs",
             with_("simulate-vehs", output="sim.mat"), mentions=["output"]))
    add(Case("model file with a term given twice", "fpk-stationary", with_("fpk-stationary", model="dupterm.json"),
             files={"dupterm.json": '{"drift": {"x": -1.0, "x": -4.0, "x^3": -1.0, "y": -0.1}, "diffusion": {"1": 0.02}}'},
             mentions=["dupterm.json"]))
    add(Case("compare: models in different units", "vehs-compare",
             with_("vehs-compare", learned="in_m.json", truth="in_mm.json"),
             files={"in_m.json": json.dumps(dict(MODEL, units={"length": "m", "time": "s"})),
                    "in_mm.json": json.dumps(dict(MODEL, units={"length": "mm", "time": "s"}))},
             mentions=["in_m.json", "in_mm.json"]))
    add(Case("simulate: output = drive file", "simulate-vehs",
             with_("simulate-vehs", model="model_u.json", drive={"path": "drive.csv"}, output="drive.csv"),
             files={"model_u.json": json.dumps({"drift": {"x": -1.0, "y": -0.1, "u": 1.0}, "diffusion": {"1": 0.01}}),
                    "drive.csv": csv_text([(0, round(0.01 * i, 2), 0.1) for i in range(501)], "traj,t,u")},
             mentions=["drive.csv"]))
    add(Case("diagnose: dt contradicting the time column", "diagnose-vehs", with_("diagnose-vehs", dt=0.5),
             mentions=["dt"]))
    # an under-resolved automatic grid is refined until the density is resolved (issue 15), never
    # reported as "heavy tails?"
    add(Case("fpk: an under-resolved automatic grid is refined", "fpk-stationary",
             with_("fpk-stationary", grid={"x": 40, "y": 40}), expect="ok",
             check=lambda d, out, err: ["'heavy tails' for a coarse grid"] if "heavy tails" in err else []))
    add(Case("fpk: sor stopped after one sweep says it did not converge", "fpk-stationary",
             with_("fpk-stationary", grid={"x": 60, "y": 60}, solver="sor", sor={"max_iterations": 1}),
             mentions=["did not converge"]))
    # ---- issue 36: values range-checked, work budgeted before it starts ----------------------
    # integers wrapped modulo 2^32 (folds 4294967298 ran as 2), negatives and fractions
    for t, key, v in (("identify-vehs", "folds", 4294967298), ("identify-vehs", "stride", 4294967297),
                      ("diagnose-vehs", "replicates", 4294967297), ("diagnose-vehs", "min_units", 4294967328),
                      ("identify-vehs", "se_block", -1), ("identify-vehs", "stride", 2.5),
                      ("simulate-vehs", "seed", 18446744073709551615)):
        add(Case(f"{key} = {v} (no wrap, no narrowing)", t, with_(t, **{key: v}), mentions=[f"'{key}'"]))
    add(Case("bins.x = 4294967312", "diagnose-vehs", with_("diagnose-vehs", bins={"x": 4294967312}),
             mentions=["'bins.x'"]))
    add(Case("fpk sweep n = 4294967298", "fpk-stationary", with_("fpk-stationary", sweep={"2D": [0.01, 0.03, 4294967298]}),
             mentions=["2D"]))
    # fpk-stationary solved a diffusion that simulate-vehs and diagnose-vehs refuse (one rule)
    # (diagnose-vehs first finds a22 < 0 at the data's samples; beyond the data, its twins' simulation
    # refuses by the same rule as the others)
    add(Case("diffusion negative for |x| > 1.41", "fpk-stationary", with_("fpk-stationary", model="negdiff.json"),
             files={"negdiff.json": json.dumps(dict(MODEL, diffusion={"1": 0.02, "x^2": -0.01}))},
             mentions=["negdiff.json: diffusion a22(x, 0) = 0.02 - 0.01·x^2 has leading term -0.01·x^2 and turns "
                       "negative at |x| = 1.414"]))
    for t in ("fpk-stationary", "simulate-vehs", "diagnose-vehs"):
        add(Case("diffusion negative for |x| > 4.47 (beyond the data)", t, with_(t, model="negdiff.json"),
                 files={"negdiff.json": json.dumps(dict(MODEL, diffusion={"1": 0.02, "x^2": -0.001}))},
                 mentions=["diffusion a22(x, 0) = 0.02 - 0.001·x^2 has leading term -0.001·x^2 and turns negative "
                           "at |x| = 4.472"]))
    # a ratio beyond the largest double: no inf or nan in the table or the file
    add(Case("compare: dev/se and rel.err beyond the largest double", "vehs-compare",
             with_("vehs-compare", learned="huge.json", truth="tiny.json"), expect="ok", check=check_finite_compare,
             files={"huge.json": json.dumps({"drift": {"x": 1e308, "y": -0.1}, "diffusion": {"1": 0.02},
                                             "stderr": {"drift": {"x": 1e-300, "y": 0.01}, "diffusion": {"1": 0.001}}}),
                    "tiny.json": json.dumps({"drift": {"x": 5e-324, "y": -0.1}, "diffusion": {"1": 0.02}})}))
    for t in TOOLS:  # stdout closed by its reader (tool ... | head -1): no death by SIGPIPE
        add(Case("stdout closed early", t, BASE[t], expect="ok", close_stdout=True))
    add(Case("simulate: x0 1e308", "simulate-vehs", with_("simulate-vehs", x0=1e308), mentions=["x0 = 1e+308"],
             check=lambda d, out, err: ["nan in the message"] if "nan" in err.lower() else []))
    add(Case("simulate: y0 -1e300", "simulate-vehs", with_("simulate-vehs", y0=-1e300), mentions=["y0 = 1e+300"]))
    add(Case("diagnose: data in physical units x1e12 diagnose like the unscaled data", "diagnose-vehs",
             with_("diagnose-vehs", model="model_e12.json", data=["data_e12.csv"]), expect="ok",
             setup=make_scaled, check=check_scaled_diagnosis))
    # budgets: refused before any work, with the estimate and how to lift it
    stats_only = dict(output=DELETE, statistics={"output": "st.json"})
    for name, changes in (("dt 1e-9 over 1e3 (2e12 steps)", dict(dt=1e-9, duration=1000)),
                          ("substeps 1e6", dict(substeps=1000000, duration=1000)),
                          ("burn_in 1e12", dict(burn_in=1e12)),
                          ("1e9 trajectories", dict(trajectories=1000000000))):
        add(Case(f"simulate budget: {name}", "simulate-vehs", with_("simulate-vehs", **stats_only, **changes),
                 mentions=["integration steps"], check=check_budget_message))
    # (4e4 whole records of 6000 samples: 24 GB of series CSV, above the output limit on any machine)
    add(Case("simulate budget: validate 4e4 segments", "simulate-vehs",
             with_("simulate-vehs", output=DELETE, validate={"data": ["data.csv"], "output": "val.json",
                                                            "segments": [{"record": 0}] * 40000}),
             mentions=["40000 segments"], check=check_budget_message))
    add(Case("fpk budget: a sweep of 1e6 points", "fpk-stationary",
             with_("fpk-stationary", sweep={"2D": [0.01, 0.03, 1000], "2Q": [0.005, 0.02, 1000]}),
             mentions=["cell solves"], check=check_budget_message))
    add(Case("fpk budget: bicgstab on 3000^2", "fpk-stationary",
             with_("fpk-stationary", grid={"x": 3000, "y": 3000}, solver="bicgstab"),
             mentions=["iterative.max_iterations"], check=check_budget_message))
    add(Case("identify budget: a 2500-monomial drift_library", "identify-vehs",
             with_("identify-vehs", drift_library=[("x" + (f"^{i}" if i > 1 else "") if i else "") +
                                                   ("*" if i and j else "") + ("y" + (f"^{j}" if j > 1 else "") if j else "")
                                                   for i in range(51) for j in range(51) if i or j][:2500]),
             mentions=["drift_library"], check=check_budget_message))
    add(Case("identify budget: study repeats 1e9", "identify-vehs",
             with_("identify-vehs", data=DELETE, study={"truth": "model.json", "dt": 0.01, "samples": 1000,
                                                          "repeats": 1000000000}),
             mentions=["repeats"], check=check_budget_message))
    add(Case("--force is the key force", "simulate-vehs", BASE["simulate-vehs"], args=["--force"], expect="ok"))

    # ---- what must work: the valid parts of the cases ------------------------------
    add(Case("fpk sweep {2D: [-0.01, 0.03, 3]}: 2D = 0.01 solved, -0.01 failed with its reason", "fpk-stationary",
             with_("fpk-stationary", sweep={"2D": [-0.01, 0.03, 3]}), expect="ok", check=check_sweep))
    add(Case("diagnose: the staged report embeds its figures", "diagnose-vehs", BASE["diagnose-vehs"], expect="ok",
             check=check_report))
    add(Case("compare: Monte Carlo without standard errors never prints nan", "vehs-compare",
             with_("vehs-compare", monte_carlo="mc.json"),
             files={"mc.json": json.dumps(dict(MC_KEYS, model=MODEL))},
             expect="ok", check=lambda d, out, err: ["nan in the table"] if "nan" in out.lower() else []))
    add(Case("a 245-byte output name is written", "identify-vehs", with_("identify-vehs", output="n" * 240 + ".json"),
             expect="ok", check=lambda d, out, err: [] if os.path.exists(os.path.join(d, "n" * 240 + ".json"))
             else ["no output"]))
    add(Case("identify: record ids up to 2^53 - 1 are read", "identify-vehs", with_("identify-vehs", data=["bigid.csv"]),
             setup=lambda d: make_big_ids(d, "data.csv", "bigid.csv", 2 ** 53 - 4), expect="ok",
             check=lambda d, out, err: []))
    add(Case("identify: glitches dropped on request", "identify-vehs", with_("identify-vehs", data=["glitch.csv"],
             glitches="drop"), setup=lambda d: make_glitch(d, "data.csv", "glitch.csv"), expect="ok",
             check=lambda d, out, err: [] if "warning: dropped 1 isolated glitch sample" in err else ["no report of the drop"]))
    # ---- signals during work or writes leave nothing behind ----------------------------------
    add(Case("SIGINT during an fpk solve", "fpk-stationary",
             with_("fpk-stationary", grid={"x": 1200, "y": 1200}, figures="figs"), expect=signal.SIGINT))
    add(Case("SIGTERM during a simulation writing a large file", "simulate-vehs",
             with_("simulate-vehs", trajectories=64, duration=2000, dt=0.01, summary="sum.json"),
             expect=signal.SIGTERM, signal_after=2.0))
    add(Case("SIGINT during a diagnosis with a report", "diagnose-vehs",
             with_("diagnose-vehs", replicates=20, suspects=True), expect=signal.SIGINT, signal_after=2.0))
    return out


def check_budget_message(d, out, err):
    return [] if '"force": true (--force)' in err and "limit" in err else ["the refusal says not how to lift it"]


def check_finite_compare(d, out, err):
    problems = [f"'{w}' printed" for w in ("inf", "nan") if w in out.lower()]
    if "overflow" not in out:
        problems.append("no overflow marker")
    with open(os.path.join(d, "cmp.csv")) as f:
        text = f.read().lower()
    return problems + [f"'{w}' in cmp.csv" for w in ("inf", "nan") if w in text]


def make_scaled(d, scale=1e12):
    """data.csv and model.json in units scale times larger (x -> s x: drift x^k y^l by s^(1-k-l),
    diffusion by s^(2-k-l))."""
    with open(os.path.join(d, "data.csv")) as f:
        lines = f.read().splitlines()
    out = [lines[0]]
    for line in lines[1:]:
        parts = line.split(",")
        parts[-1] = repr(float(parts[-1]) * scale)
        out.append(",".join(parts))
    with open(os.path.join(d, "data_e12.csv"), "w") as f:
        f.write("\n".join(out) + "\n")

    def power(term):
        k = l = 0
        for f in term.split("*"):
            if f.startswith("x"):
                k = int(f[2:]) if f.startswith("x^") else 1
            elif f.startswith("y"):
                l = int(f[2:]) if f.startswith("y^") else 1
        return k + l
    model = {"drift": {t: c * scale ** (1 - power(t)) for t, c in MODEL["drift"].items()},
             "diffusion": {t: c * scale ** (2 - power(t)) for t, c in MODEL["diffusion"].items()}}
    with open(os.path.join(d, "model_e12.json"), "w") as f:
        json.dump(model, f)


def check_scaled_diagnosis(d, out, err):
    if not os.path.exists(os.path.join(d, "diag.json")):
        return []  # (the failure is reported)
    with open(os.path.join(d, "diag.json")) as f:
        scaled = json.load(f)
    cfg = dict(BASE["diagnose-vehs"], output="diag_unscaled.json")
    with open(os.path.join(d, "unscaled.json"), "w") as f:
        json.dump(cfg, f)
    p = subprocess.run([os.path.join(BINDIR, "diagnose-vehs"), "-q", "unscaled.json"], cwd=d, capture_output=True)
    if p.returncode != 0:
        return ["the unscaled data failed: " + p.stderr.decode()[:200]]
    with open(os.path.join(d, "diag_unscaled.json")) as f:
        unscaled = json.load(f)
    return [] if scaled["verdict"] == unscaled["verdict"] else [f"verdict {scaled['verdict']} != {unscaled['verdict']}"]


def check_stderr_method(d, out, err):
    with open(os.path.join(d, "learned.json")) as f:
        method = json.load(f)["fit"]["stderr_method"]
    return [] if "rows on average (target 512 rows per batch" in method else [f"stderr_method: {method}"]


def check_report(d, out, err):
    if shutil.which("gnuplot") is None:
        return []
    with open(os.path.join(d, "diag_report", "index.html")) as f:
        html = f.read()
    problems = [] if "data:image/svg+xml" in html else ["no figure embedded in index.html"]
    if "figure not rendered" in html:
        problems.append("index.html says a figure was not rendered")
    leftovers = [n for n in os.listdir(d) + os.listdir(os.path.join(d, "diag_report")) if n.startswith(".vehs")]
    return problems + (["left: " + ", ".join(leftovers)] if leftovers else [])


def check_sweep(d, out, err):
    problems = []
    with open(os.path.join(d, "fpk.sweep.csv")) as f:
        rows = [r.split(",") for r in f.read().splitlines()]
    ok = {r[0]: r[-1] for r in rows[1:]}
    if ok != {"-0.01": "0", "0.01": "1", "0.03": "1"}:
        problems.append(f"sweep rows ok = {ok}")
    for root, _dirs, files in os.walk(d):
        for name in files:
            with open(os.path.join(root, name), "rb") as f:
                if b"nan" in f.read().lower():
                    problems.append(f"{name} holds nan")
    if "2D = -0.01 failed: " not in err or "negative" not in err:
        problems.append("the failed point's reason is not reported")
    return problems


def make_duplicate_column(d, src, dst):  # traj,t,x,x: the second x differs
    with open(os.path.join(d, src)) as f:
        lines = f.read().splitlines()
    out = [lines[0] + ",x"] + [ln + ",0.25" for ln in lines[1:]]
    with open(os.path.join(d, dst), "w") as f:
        f.write("\n".join(out) + "\n")


def make_bom(d, src, dst):
    with open(os.path.join(d, src), encoding="utf-8") as f:
        text = f.read()
    with open(os.path.join(d, dst), "w", encoding="utf-8") as f:
        f.write("\ufeff" + text)


def make_offset(d, src, dst):
    with open(os.path.join(d, src)) as f:
        lines = f.read().splitlines()
    out = [lines[0]]
    for line in lines[1:]:
        parts = line.split(",")
        parts[-1] = repr(1000.0 + float(parts[-1]))
        out.append(",".join(parts))
    with open(os.path.join(d, dst), "w") as f:
        f.write("\n".join(out) + "\n")


def make_dropout(d, src, dst):
    with open(os.path.join(d, src)) as f:
        lines = f.read().splitlines()
    k = len(lines) // 3 + 500  # 30 samples inside a record written as 0 (how loggers write a dropout)
    for i in range(k, k + 30):
        parts = lines[i].split(",")
        parts[-1] = "0"
        lines[i] = ",".join(parts)
    with open(os.path.join(d, dst), "w") as f:
        f.write("\n".join(lines) + "\n")


def make_glitch(d, src, dst):
    with open(os.path.join(d, src)) as f:
        lines = f.read().splitlines()
    k = len(lines) // 3 + 777  # inside a record
    parts = lines[k].split(",")
    parts[-1] = "0.5" if abs(float(parts[-1]) - 0.5) > 0.3 else "-0.9"
    lines[k] = ",".join(parts)
    with open(os.path.join(d, dst), "w") as f:
        f.write("\n".join(lines) + "\n")


def make_truncated_end(d, src, dst):  # a logger killed mid-write: the file ends in "3,59.87,0."
    with open(os.path.join(d, src)) as f:
        lines = f.read().splitlines()
    last = max(i for i in range(len(lines) - 200, len(lines)) if abs(float(lines[i].split(",")[-1])) > 0.3)
    parts = lines[last].split(",")
    parts[-1] = parts[-1][:parts[-1].index(".") + 1]
    with open(os.path.join(d, dst), "w") as f:
        f.write("\n".join(lines[:last] + [",".join(parts)]) + "\n")


def make_zero_start(d, src, dst):  # the record whose first x is farthest from 0 starts with a 0
    with open(os.path.join(d, src)) as f:
        lines = f.read().splitlines()
    starts = [i for i in range(1, len(lines)) if i == 1 or lines[i].split(",")[0] != lines[i - 1].split(",")[0]]
    k = max(starts, key=lambda i: abs(float(lines[i].split(",")[-1])))
    parts = lines[k].split(",")
    parts[-1] = "0"
    lines[k] = ",".join(parts)
    with open(os.path.join(d, dst), "w") as f:
        f.write("\n".join(lines) + "\n")


def make_big_ids(d, src, dst, first):  # the records' ids counted from `first` (2^53 - 4: the largest ids)
    with open(os.path.join(d, src)) as f:
        lines = f.read().splitlines()
    out = [lines[0]]
    for line in lines[1:]:
        parts = line.split(",")
        parts[0] = str(first + int(parts[0]))
        out.append(",".join(parts))
    with open(os.path.join(d, dst), "w") as f:
        f.write("\n".join(out) + "\n")


def write_mat_v4(path, columns):  # MATLAB v4: per variable a header, its name and float64 values
    with open(path, "wb") as f:
        for name, values in columns.items():
            f.write(struct.pack("<5i", 0, len(values), 1, 0, len(name) + 1) + name.encode() + b"\0")
            f.write(struct.pack(f"<{len(values)}d", *values))


def make_fractional_id_mat(d):  # two records labelled 0.2 and 0.7 (they were read as one)
    n = 400
    write_mat_v4(os.path.join(d, "ids.mat"), {
        "traj": [0.2 if i < n else 0.7 for i in range(2 * n)],
        "t": [0.01 * (i % n) for i in range(2 * n)],
        "x": [math.sin(0.05 * i) for i in range(2 * n)]})


def make_subarray_npy(d):  # dtype [('t', '<f8'), ('x', '<f8', (2,))]
    header = "{'descr': [('t', '<f8'), ('x', '<f8', (2,))], 'fortran_order': False, 'shape': (100,), }"
    header += " " * (63 - (10 + len(header)) % 64) + "\n"
    with open(os.path.join(d, "sub.npy"), "wb") as f:
        f.write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode())
        for i in range(100):
            f.write(struct.pack("<3d", 0.01 * i, math.sin(0.05 * i), math.cos(0.05 * i)))


def make_corrupt_mat73(d):  # a v7.3 header (HDF5 inside) followed by garbage
    head = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Mon Jan  5 10:00:00 2026 HDF5 schema 1.00 ."
    head = head.ljust(116, b" ") + b"\0" * 8 + b"\x00\x02IM"
    with open(os.path.join(d, "bad73.mat"), "wb") as f:
        f.write(head.ljust(512, b"\0") + b"garbage" * 60)


def make_socket(d):
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    s.bind(os.path.join(d, "sock.csv"))
    s.close()


def snapshot(d):
    out = {}
    for root, dirs, files in os.walk(d):
        for name in dirs + files:
            p = os.path.join(root, name)
            st = os.lstat(p)
            digest = ""
            if os.path.isfile(p) and not os.path.islink(p):
                with open(p, "rb") as f:
                    digest = hashlib.sha1(f.read()).hexdigest()
            out[os.path.relpath(p, d)] = (st.st_mode, st.st_ino, st.st_size, digest,
                                          os.readlink(p) if os.path.islink(p) else "")
    return out


def run_case(case, bindir, fixtures, workdir, timeout):
    d = tempfile.mkdtemp(prefix="case_", dir=workdir)
    for name in os.listdir(fixtures):
        shutil.copy(os.path.join(fixtures, name), d)
    for name, text in case.files.items():
        with open(os.path.join(d, name), "w", encoding="utf-8", errors="surrogateescape") as f:
            f.write(text)
    if case.config_name:
        with open(os.path.join(d, case.config_name), "w", encoding="utf-8") as f:
            f.write(case.raw if case.raw is not None else json.dumps(case.config))
    if case.setup:
        case.setup(d)
    before = snapshot(d)
    cmd = [os.path.join(bindir, case.tool), "-q"] + ([case.config_name] if case.config_name else []) + case.args
    t0 = time.time()
    out = ""
    try:
        if case.close_stdout:  # without -q: every tool prints its summary on stdout
            cmd = [c for c in cmd if c != "-q"]
        p = subprocess.Popen(cmd, cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             env=dict(os.environ, OMP_NUM_THREADS="1"))
        if case.close_stdout:
            p.stdout.close()
            p.stdout = None
        if isinstance(case.expect, int):
            time.sleep(case.signal_after)
            p.send_signal(case.expect)
        o, e = p.communicate(timeout=timeout)
        rc, err, out = p.returncode, e.decode("utf-8", "replace"), (o or b"").decode("utf-8", "replace")
    except subprocess.TimeoutExpired:
        p.kill()
        p.communicate()
        rc, err = "timeout", ""
    seconds = time.time() - t0
    problems = []
    if "Sanitizer" in err or "runtime error:" in err:  # a sanitized build (.ci/run's ASan step)
        problems.append("sanitizer report: " + next(ln for ln in err.splitlines() if "Sanitizer" in ln or "runtime error" in ln))
    if case.expect == "ok" or isinstance(case.expect, int):
        if rc == "timeout":
            problems.append(f"no answer within {timeout} s (hang)")
        elif case.expect == "ok" and rc != 0:
            problems.append(f"exit status {rc}: {err.strip()[:200]}")
        elif isinstance(case.expect, int) and rc != 128 + case.expect:
            problems.append(f"exit status {rc}, not {128 + case.expect}")
        if case.check and rc != "timeout":
            problems += case.check(d, out, err)
        if isinstance(case.expect, int):
            after = snapshot(d)
            changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
            if changed:
                problems.append("files left behind: " + ", ".join(changed[:6]))
        shutil.rmtree(d, ignore_errors=True)
        return problems, err.strip()[:300], seconds
    if rc == "timeout":
        problems.append(f"no answer within {timeout} s (hang)")
    elif rc == 0:
        problems.append("exit status 0")
    elif rc < 0 or rc >= 128:
        problems.append(f"killed by a signal / crashed (status {rc})")
    lines = [ln for ln in err.splitlines() if ln.strip()]
    if rc != "timeout" and len(lines) != 1:
        problems.append(f"{len(lines)} lines on stderr")
    if case.mentions and rc != "timeout" and not any(m in err for m in case.mentions):
        problems.append("stderr names none of " + ", ".join(case.mentions))
    if case.check and rc != "timeout":
        problems += case.check(d, out, err)
    after = snapshot(d)
    changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
    if changed:
        problems.append("files changed: " + ", ".join(changed[:6]))
    for root, _dirs, _files in os.walk(d):  # the unwritable folders of some cases
        os.chmod(root, 0o755)
    shutil.rmtree(d, ignore_errors=True)
    return problems, err.strip()[:300], seconds


def make_fixtures(bindir, d):
    with open(os.path.join(d, "model.json"), "w") as f:
        json.dump(MODEL, f)
    cfg = {"model": "model.json", "trajectories": 4, "duration": 60, "dt": 0.01, "seed": 5,
           "x0": {"uniform": [-1.0, 1.0]}, "record_velocity": False, "output": "data.csv"}
    with open(os.path.join(d, "gen.json"), "w") as f:
        json.dump(cfg, f)
    subprocess.run([os.path.join(bindir, "simulate-vehs"), "-q", "gen.json"], cwd=d, check=True)
    os.remove(os.path.join(d, "gen.json"))


def check_bases(bindir, fixtures, workdir, timeout):
    bad = []
    for t, cfg in BASE.items():
        d = tempfile.mkdtemp(prefix="base_", dir=workdir)
        for name in os.listdir(fixtures):
            shutil.copy(os.path.join(fixtures, name), d)
        with open(os.path.join(d, "cfg.json"), "w") as f:
            json.dump(cfg, f)
        try:
            p = subprocess.run([os.path.join(bindir, t), "-q", "cfg.json"], cwd=d, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, timeout=timeout * 3)
            if p.returncode != 0:
                bad.append(f"{t}: base config fails ({p.returncode}): {p.stderr.decode()[:300]}")
        except subprocess.TimeoutExpired:
            bad.append(f"{t}: base config takes longer than {timeout * 3} s")
        shutil.rmtree(d, ignore_errors=True)
    return bad


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bindir")
    ap.add_argument("--only", default="")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--timeout", type=float, default=20.0)
    ap.add_argument("--verbose", action="store_true")
    a = ap.parse_args()
    a.bindir = os.path.abspath(a.bindir)
    global BINDIR
    BINDIR = a.bindir
    all_cases = [c for c in cases() if a.only in f"{c.tool}: {c.name}"]
    if a.list:
        for c in all_cases:
            print(f"{c.tool}: {c.name}")
        print(len(all_cases), "cases")
        return 0
    workdir = tempfile.mkdtemp(prefix="vehs_bad_inputs_")
    fixtures = os.path.join(workdir, "fixtures")
    os.mkdir(fixtures)
    make_fixtures(a.bindir, fixtures)
    failures = check_bases(a.bindir, fixtures, workdir, a.timeout)
    for f in failures:
        print("FAIL", f)
    t0 = time.time()
    slowest = (0.0, "")
    for c in all_cases:
        problems, err, seconds = run_case(c, a.bindir, fixtures, workdir, a.timeout)
        slowest = max(slowest, (seconds, f"{c.tool}: {c.name}"))
        if problems and c.owner:
            print(f"KNOWN ({c.owner}) {c.tool}: {c.name}: {'; '.join(problems)}\n     stderr: {err}")
        elif problems:
            failures.append(c.name)
            print(f"FAIL {c.tool}: {c.name}: {'; '.join(problems)}\n     stderr: {err}")
        elif a.verbose:
            print(f"ok   {c.tool}: {c.name} ({seconds:.2f} s): {err}")
    shutil.rmtree(workdir, ignore_errors=True)
    print(f"{len(all_cases)} bad inputs, {len(failures)} failures, {time.time() - t0:.1f} s "
          f"(slowest {slowest[0]:.1f} s: {slowest[1]})")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
