"""Build of the compiled core, ``flexmbd.engine._core`` (C, no dependencies beyond a compiler and
the Python headers). Everything else is in pyproject.toml."""

import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCES = ["flexmbd/engine/csrc/module.c", "flexmbd/engine/csrc/system.c", "flexmbd/engine/csrc/alpha.c",
           "flexmbd/engine/csrc/band.c", "flexmbd/engine/csrc/text.c", "flexmbd/engine/csrc/kernels.c"]
FLAGS = ["-O3", "-std=c99", "-fno-math-errno"]


class BuildCore(build_ext):
    """build_ext that names what is missing when the core cannot be compiled, and that
    compiles the package's bytecode where the build is in place (``pip install -e .``):
    pip does so for a regular installation, and without it every run where bytecode is
    not written (``PYTHONDONTWRITEBYTECODE``) compiles flexmbd afresh, 20 to 40 ms."""

    def run(self):
        super().run()
        if self.inplace:
            import compileall

            for folder in ("flexmbd", "examples"):
                compileall.compile_dir(folder, quiet=1)

    def build_extensions(self):
        compiler = getattr(self.compiler, "compiler_so", ["cc"])[0]
        for extension in self.extensions:
            extension.define_macros.append(
                ("FLEXMBD_BUILD", f'"C, {compiler} {" ".join(FLAGS)}"'))
        try:
            super().build_extensions()
        except Exception as error:
            include = sysconfig.get_paths()["include"]
            raise SystemExit(
                f"flexmbd: cannot compile its core (flexmbd.engine._core): {error}\n"
                f"flexmbd needs a C compiler ({compiler}) and the Python headers "
                f"(Python.h in {include}); on Debian or Ubuntu: apt install gcc python3-dev"
            ) from None


setup(ext_modules=[Extension("flexmbd.engine._core", SOURCES, extra_compile_args=FLAGS,
                             depends=["flexmbd/engine/csrc/core.h", "flexmbd/engine/csrc/alpha.h",
                                      "flexmbd/engine/csrc/text.h"])],
      cmdclass={"build_ext": BuildCore})
