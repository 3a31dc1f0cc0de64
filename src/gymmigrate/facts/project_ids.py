"""Where a module hands an env id literal to a def of the run that makes it
(``ProjectFacts.id_slots``): a pass of ``ProjectFacts.join`` over ``ModuleSummary.id_params``.

``MultiEnv("Pendulum-v0", 8)`` in the run script, with ``make(self.env_id)`` in the module
that defines ``MultiEnv``: the script's literal is the id, renamed (or reported) there. A
def that hands its own parameter on to such a def (``param:`` kinds) takes ids too, so a
chain across modules is followed, a few rounds deep.
"""

from __future__ import annotations

from collections import defaultdict

from gymmigrate.facts.module_summary import PARAM, CallSummary, ModuleSummary, Signature

# rounds of ``param:`` hand-offs followed across modules
_ROUNDS = 4


def id_slots(by_path: dict[str, ModuleSummary], calls_to: dict[tuple[str, str], list[tuple[str, CallSummary]]]) -> dict[str, frozenset[tuple[int, str]]]:
    """caller path -> (line, argument key: its position as a string, or the keyword) of each
    call that passes an env id literal to an id parameter of a def of the run."""
    params: dict[tuple[str, str], set[str]] = defaultdict(set)
    for path, summary in by_path.items():
        for qualname, names in summary.id_params.items():
            params[(path, qualname)].update(names)
    for _ in range(_ROUNDS):
        grew = False
        for (path, qualname), calls in calls_to.items():
            wanted = params.get((path, qualname))
            signature = by_path[path].defs.get(qualname)
            if not wanted or signature is None:
                continue
            for caller, call in calls:
                for key, kind in _arguments(signature, call):
                    if key in wanted and isinstance(kind, str) and kind.startswith(PARAM):
                        def_name, _, param = kind[len(PARAM) :].rpartition(":")
                        if param not in params[(caller, def_name)]:
                            params[(caller, def_name)].add(param)
                            grew = True
        if not grew:
            break
    slots: dict[str, set[tuple[int, str]]] = defaultdict(set)
    for (path, qualname), calls in calls_to.items():
        wanted = params.get((path, qualname))
        signature = by_path[path].defs.get(qualname)
        if not wanted or signature is None:
            continue
        positional = list(signature.params[1:] if signature.is_method else signature.params)
        for caller, call in calls:
            for key, _ in call.ids:
                param = positional[int(key)] if key.isdigit() and int(key) < len(positional) else key
                if param in wanted:
                    slots[caller].add((call.line, key))
    return {path: frozenset(found) for path, found in slots.items()}


def _arguments(signature: Signature, call: CallSummary) -> list[tuple[str, object]]:
    positional = list(signature.params[1:] if signature.is_method else signature.params)
    found: list[tuple[str, object]] = [(positional[i], kind) for i, kind in enumerate(call.args) if i < len(positional)]
    found += list(call.keywords)
    return found
