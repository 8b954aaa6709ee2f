# SPDX-License-Identifier: BSD-3-Clause
# A Spack recipe for nacre, after the examinimd and cabana recipes: nacre builds with the user's
# Kokkos, whatever its backend. From a checkout (no public download is named here):
#   spack repo add packaging/spack
#   spack dev-build -d . nacre@1.0.0 +mpi ^kokkos+openmp      (or +cuda cuda_arch=90 ^kokkos+cuda)
# Spack itself is not run by nacre's CI (it is not installable offline); tests/packaging/
# check_spack_recipe.py runs this recipe's cmake_args() through a stand-in for Spack's package API
# and configures nacre with them, for each variant combination.
from spack.package import *


class Nacre(CMakePackage, CudaPackage):
    """Fracture of brick-and-mortar composites (nacre) on Kokkos: rigid bricks with cohesive
    mortar relaxed by Monte Carlo or Newton, deformable bricks in time (explicit and bolted
    implicit-explicit), constant-time AES-128 random numbers."""

    license("BSD-3-Clause")

    version("1.0.0")

    variant("mpi", default=False, description="Domain decomposition over MPI ranks")
    variant("kokkos-kernels", default=True, description="Kokkos Kernels colouring and BIE solve variants")
    variant("cholmod", default=True, description="CHOLMOD for the Newton factor")
    variant("tests", default=False, description="Build the Catch2 test suite")

    depends_on("cxx", type="build")
    depends_on("cmake@3.22:", type="build")
    depends_on("kokkos@4.6:")
    depends_on("kokkos-kernels@4.6:", when="+kokkos-kernels")
    depends_on("eigen@3.3:")
    depends_on("hdf5~mpi", when="~mpi")
    depends_on("hdf5", when="+mpi")
    depends_on("tomlplusplus@3:")
    depends_on("cli11@2:")
    depends_on("nlohmann-json@3:")
    depends_on("suite-sparse", when="+cholmod")
    depends_on("mpi", when="+mpi")
    depends_on("catch2@3:", type="test", when="+tests")
    depends_on("python@3.9:", type="run")
    depends_on("py-numpy", type="run")
    depends_on("py-h5py", type="run")
    depends_on("py-matplotlib", type="run")
    # a CUDA nacre needs a CUDA Kokkos, compiled through its nvcc_wrapper
    for arch in CudaPackage.cuda_arch_values:
        depends_on(f"kokkos+cuda+wrapper cuda_arch={arch}", when=f"+cuda cuda_arch={arch}")

    def cmake_args(self):
        spec = self.spec
        args = [
            self.define_from_variant("NACRE_ENABLE_MPI", "mpi"),
            self.define_from_variant("NACRE_ENABLE_KOKKOSKERNELS", "kokkos-kernels"),
            self.define_from_variant("NACRE_ENABLE_CHOLMOD", "cholmod"),
            self.define_from_variant("NACRE_ENABLE_TESTS", "tests"),
            self.define("NACRE_ENABLE_PERF", False),
            self.define("Kokkos_ROOT", spec["kokkos"].prefix),
            # Kokkos' compiler: its nvcc_wrapper for a CUDA Kokkos, else Spack's C++ compiler
            self.define("CMAKE_CXX_COMPILER", self["kokkos"].kokkos_cxx),
        ]
        if spec.satisfies("+kokkos-kernels"):
            args.append(self.define("KokkosKernels_ROOT", spec["kokkos-kernels"].prefix))
        return args
