"""The names the semlb binary registers (`semlb list KIND --json`): how every analysis script learns policy, effect,
backend and cell-type names instead of typing them again."""
import json
import subprocess


class NamesError(Exception):
    """The binary could not list a kind; str() is one line naming the command and what went wrong."""


def names(semlb, kind):
    """The names the binary SEMLB registers for KIND (one of kinds(SEMLB)), in its order (by type index for
    cell-types, by name otherwise): `semlb list KIND --json`. Raises NamesError naming the binary when it is missing, fails or prints
    something other than a JSON array of strings."""
    cmd = f"{semlb} list {kind} --json"
    try:
        out = subprocess.run([semlb, "list", kind, "--json"], capture_output=True, text=True, timeout=60)
    except FileNotFoundError:
        raise NamesError(f"{cmd}: no binary at '{semlb}' (build it with `make build` or pass --semlb)") from None
    except (OSError, subprocess.SubprocessError) as e:
        raise NamesError(f"{cmd}: {e}") from None
    if out.returncode != 0:
        raise NamesError(f"{cmd}: exit {out.returncode}: {(out.stderr.strip().splitlines() or [''])[-1]}")
    try:
        got = json.loads(out.stdout)
    except ValueError:
        got = None
    if not isinstance(got, list) or not all(isinstance(n, str) for n in got):
        raise NamesError(f"{cmd}: not a JSON array of names: {out.stdout.strip()[:80]!r}")
    return got


def kinds(semlb):
    """The kinds the binary SEMLB lists (`semlb list kinds --json`: its catalogue of registries, e.g. policies,
    backends, pair-terms), in name order; NamesError as names()."""
    return names(semlb, "kinds")
