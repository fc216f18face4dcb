"""``pframe compile``: compile the installed plug-in laws ahead of time.

pframe's kernel is C, compiled when pframe is installed: built-in laws need no compiling at
run time. Plug-in laws (entry points in ``pframe.contact_laws`` and ``pframe.materials``) are
compiled by numba into C functions the kernel calls, once per set of plug-ins and cached
(:mod:`pframe.kernel.plugins`); this command does it for every installed plug-in law, so that
nobody's first run waits for it (installers, CI, shared machines). With no plug-in installed
it checks that the compiled kernel loads and says that nothing needs compiling.
"""

from __future__ import annotations

import sys
import time


def _compile(args) -> int:
    from pframe.errors import InputError
    from pframe.kernel import ckernel
    from pframe.laws import registry

    start = time.perf_counter()
    library = ckernel.library()
    path = getattr(library, "_name", "")
    plugins = [registry.get_law(kind, name)
               for kind in ("material", "contact")
               for name in sorted(set(registry.available_names(kind))
                                  - set(registry.builtin_names(kind)))]
    if not plugins:
        print(f"nothing to compile: the kernel was compiled when pframe was installed ({path}) "
              "and no plug-in law is installed")
        return 0
    from pframe.kernel import plugins as plugin_kernel

    compiled, failed = [], []
    for law in plugins:  # one at a time, so that one law numba cannot compile spoils no other
        try:
            plugin_kernel.compiled((law,), announce=lambda message: print(
                f"pframe: {message}", file=sys.stderr, flush=True))
            compiled.append(law.name)
        except InputError as exc:
            failed.append(str(exc))
    seconds = time.perf_counter() - start
    if compiled:
        print(f"compiled the plug-in laws {', '.join(compiled)} in {seconds:.1f} s (cached in "
              f"{plugin_kernel.root() / 'plugins'})")
    for message in failed:
        print(f"pframe: error: {message}", file=sys.stderr)
    return 2 if failed else 0


def register(sub) -> None:
    parser = sub.add_parser("compile", help="compile the installed plug-in laws now (the "
                                            "kernel itself is compiled at install)")
    parser.set_defaults(run=_compile)
