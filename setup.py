"""Build the compiled kernels: one Cython extension per ``_*.pyx`` under ``src/pds_plugin``.

OpenMP is used when the compiler supports it (gcc, or clang with libomp); without it
the kernels are built serial, with a warning. The kernels are compiled without fused
multiply-add (``-ffp-contract=off``) and without fast-math, so every float result is
the same as the plain IEEE operations in the order written.
"""

import os
import tempfile
from pathlib import Path

import numpy
from Cython.Build import cythonize
from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

KERNELS = sorted(Path("src").glob("pds_plugin/**/_*.pyx"))     # wherever the package puts them


class BuildKernels(build_ext):
    """build_ext adding OpenMP if the compiler has it, and exact float flags."""

    def finalize_options(self):
        super().finalize_options()
        if not self.parallel:
            self.parallel = os.cpu_count() or 1      # compile the modules side by side

    def build_extensions(self):
        msvc = self.compiler.compiler_type == "msvc"
        openmp = ["/openmp"] if msvc else ["-fopenmp"]
        if not self._compiles(openmp):
            self.warn("building the pds_plugin kernels without OpenMP: they will run in one "
                      "thread (install gcc, or clang with libomp, for parallel kernels)")
            openmp = []
        exact = ["/fp:precise"] if msvc else ["-O3", "-ffp-contract=off", "-fno-fast-math"]
        for extension in self.extensions:
            extension.extra_compile_args += exact + openmp
            extension.extra_link_args += openmp
        super().build_extensions()

    def _compiles(self, flags) -> bool:
        """True if a small OpenMP program compiles and links with ``flags``."""
        with tempfile.TemporaryDirectory() as folder:
            source = Path(folder) / "openmp_check.c"
            source.write_text("#include <omp.h>\n"
                              "int main(void) { return omp_get_max_threads() > 0 ? 0 : 1; }\n")
            try:
                objects = self.compiler.compile([str(source)], output_dir=folder,
                                                extra_postargs=flags)
                self.compiler.link_executable(objects, "openmp_check", output_dir=folder,
                                              extra_postargs=flags)
            except Exception:       # CompileError, LinkError: no usable OpenMP
                return False
        return True


extensions = [Extension(".".join(path.relative_to("src").with_suffix("").parts), [str(path)],
                        include_dirs=[numpy.get_include()],
                        define_macros=[("NPY_NO_DEPRECATED_API", "NPY_1_7_API_VERSION")])
              for path in KERNELS]

setup(ext_modules=cythonize(extensions, compiler_directives={"language_level": 3}),
      cmdclass={"build_ext": BuildKernels})
