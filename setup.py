"""Builds pframe's C kernel (the extension pframe.kernel._ckernel); everything else about the
package is in pyproject.toml.

The kernel is C99 compiled with -O2 and IEEE arithmetic (no -ffast-math, no contraction into
fused multiply-adds), so that results are the same bits on every machine that has the same
libm. It uses no Python API (the driver calls it through ctypes), so the extension is built
for the limited API: one wheel per platform serves every Python from 3.10.
"""

import hashlib
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

C = Path("framework") / "pframe" / "kernel" / "c"


def source_hash() -> str:
    """What pframe.kernel.ckernel.source_hash computes from the installed sources: a kernel
    built from other sources is refused at load time."""
    digest = hashlib.sha256()
    for path in sorted(p for p in C.glob("*") if p.suffix in (".c", ".h")):
        digest.update(path.name.encode())
        digest.update(path.read_bytes().replace(b"\r\n", b"\n"))
    return "h" + digest.hexdigest()[:16]


class BuildKernel(build_ext):
    """Compiler flags by compiler: IEEE arithmetic and C99 everywhere."""

    def build_extensions(self):
        if self.compiler.compiler_type == "msvc":
            flags = ["/O2", "/fp:precise"]
        else:
            flags = ["-std=c99", "-O2", "-ffp-contract=off", "-fno-fast-math", "-fvisibility=hidden"]
        for extension in self.extensions:
            extension.extra_compile_args = list(flags)
            if extension.name == "pframe.excitation._cstochastic" and "-O2" in flags:
                # its loops over pulses vectorise at -O3 (no reductions: same results)
                extension.extra_compile_args[flags.index("-O2")] = "-O3"
        super().build_extensions()

    def run(self):
        super().run()
        if self.inplace:
            # pip install -e .: the package is the source tree, which pip does not byte-compile
            # as it does an installed wheel. Compile it now, like the kernel: a process that
            # may not write bytecode (PYTHONDONTWRITEBYTECODE, a read-only checkout) would
            # otherwise compile pframe's modules from source at every start, a quarter of a
            # warm `pframe solve` here. A module edited later is compiled again when imported.
            import compileall

            compileall.compile_dir(str(Path("framework") / "pframe"), quiet=1)


kernel = Extension(
    "pframe.kernel._ckernel",
    sources=[str(C / "kernel.c"), str(C / "module.c")],
    depends=[str(p) for p in sorted(C.glob("*")) if p.suffix in (".c", ".h")],
    define_macros=[("PFRAME_SOURCE_HASH", source_hash()), ("Py_LIMITED_API", "0x030A0000")],
    py_limited_api=True,
)

# the filter of the stochastic ground motions (pframe.excitation.stochastic), also through ctypes
stochastic = Extension(
    "pframe.excitation._cstochastic",
    sources=[str(Path("framework") / "pframe" / "excitation" / "c" / "rezaeian.c")],
    define_macros=[("Py_LIMITED_API", "0x030A0000")],
    py_limited_api=True,
)

setup(ext_modules=[kernel, stochastic], cmdclass={"build_ext": BuildKernel},
      options={"bdist_wheel": {"py_limited_api": "cp310"}})
