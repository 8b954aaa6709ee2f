# SPDX-License-Identifier: BSD-3-Clause
"""The Spack recipe (packaging/spack/packages/nacre/package.py) without Spack.

Spack is not installable offline, so CI cannot run `spack install nacre`. This check runs the
recipe through a stand-in for the part of Spack's package API it uses (the directives, a spec
with variants, CMakePackage.define / define_from_variant with Spack's spelling of -D options) and
then configures nacre with the options it returns for three variant sets (the defaults, all on,
all off; a set needing MPI, Kokkos Kernels or CHOLMOD where absent is left out and said so; CUDA
is not configured here):

  1. every variant that cmake_args() reads is declared, every dependency is spelt as Spack's
     builtin repository spells it;
  2. `cmake` accepts the options: configure succeeds and reports no "Manually-specified variables
     were not used" (an option the project does not know).

  check_spack_recipe.py SOURCE_DIR WORK_DIR KOKKOS_PREFIX [KOKKOS_KERNELS_PREFIX]
"""
import os
import shutil
import subprocess
import sys
import types

SRC, WORK, KOKKOS = sys.argv[1], sys.argv[2], sys.argv[3]
KK = sys.argv[4] if len(sys.argv) > 4 and sys.argv[4] and not sys.argv[4].endswith("NOTFOUND") else None

# Spack's builtin names of what the recipe may depend on (packages.spack.io; a misspelt name is a
# concretisation error for every user)
SPACK_NAMES = {"cxx", "cmake", "kokkos", "kokkos-kernels", "eigen", "hdf5", "tomlplusplus", "cli11",
               "nlohmann-json", "suite-sparse", "mpi", "catch2", "python", "py-numpy", "py-h5py",
               "py-matplotlib", "cuda"}

directives = {"variants": {}, "depends": [], "versions": [], "conflicts": []}


def variant(name, default=None, description="", **kw):
    directives["variants"][name] = default


def depends_on(spec, when=None, type=None):
    directives["depends"].append((spec, when))


def version(v, **kw):
    directives["versions"].append(v)


def license(*a, **kw):
    pass


def conflicts(*a, **kw):
    directives["conflicts"].append(a)


def maintainers(*a):
    pass


class Spec:
    """The concretised spec of nacre: its variants, and its dependencies' prefixes."""

    def __init__(self, variants):
        self.variants = variants

    def satisfies(self, s):
        s = s.strip()
        if s.startswith("^kokkos+cuda"):
            return self.variants.get("cuda", False)
        if s[0] in "+~":
            name = s[1:]
            if name not in self.variants:
                raise KeyError(f"the recipe asks for variant '{name}', which it does not declare")
            return self.variants[name] == (s[0] == "+")
        raise NotImplementedError(f"stand-in spec cannot answer satisfies({s!r})")

    def __getitem__(self, name):
        prefix = {"kokkos": KOKKOS, "kokkos-kernels": KK}.get(name)
        if prefix is None:
            raise KeyError(f"no stand-in prefix for dependency {name}")
        return types.SimpleNamespace(prefix=prefix)


class CMakePackage:
    def __init__(self, spec):
        self.spec = spec

    def __getitem__(self, name):  # self["kokkos"]: the dependency's package
        assert name == "kokkos", name
        return types.SimpleNamespace(kokkos_cxx=os.environ.get("CXX", "c++"))

    @staticmethod
    def define(name, value):
        if isinstance(value, bool):
            return f"-D{name}:BOOL={'ON' if value else 'OFF'}"
        return f"-D{name}:STRING={value}"

    def define_from_variant(self, name, variant_name):
        if variant_name not in directives["variants"]:
            raise KeyError(f"define_from_variant({name!r}, {variant_name!r}): no such variant in the recipe")
        return self.define(name, bool(self.spec.variants[variant_name]))


class CudaPackage:
    cuda_arch_values = ("70", "80", "90")
    # (CudaPackage declares +cuda and cuda_arch itself)
    variant("cuda", default=False)


spack = types.ModuleType("spack")
pkg = types.ModuleType("spack.package")
for k, v in dict(variant=variant, depends_on=depends_on, version=version, license=license, conflicts=conflicts,
                 maintainers=maintainers, CMakePackage=CMakePackage, CudaPackage=CudaPackage).items():
    setattr(pkg, k, v)
pkg.__all__ = list(vars(pkg))
sys.modules["spack"], sys.modules["spack.package"] = spack, pkg

path = os.path.join(SRC, "packaging", "spack", "packages", "nacre", "package.py")
ns = {}
exec(compile(open(path).read(), path, "exec"), ns)
Nacre = ns["Nacre"]

fails = 0
for spec, _ in directives["depends"]:
    name = spec.split("@")[0].split("+")[0].split("~")[0].split(" ")[0]
    if name not in SPACK_NAMES:
        print(f"FAIL: depends_on({spec!r}): '{name}' is not a Spack package name")
        fails += 1
print(f"recipe: version {directives['versions']}, variants {sorted(directives['variants'])}, "
      f"{len(directives['depends'])} dependencies")

project_version = None
for line in open(os.path.join(SRC, "CMakeLists.txt")):
    if "VERSION" in line and line.strip().startswith("project("):
        project_version = line.split("VERSION")[1].split()[0].rstrip(")")
if project_version not in directives["versions"]:
    print(f"FAIL: the recipe's versions {directives['versions']} lack the project's {project_version}")
    fails += 1

have = {"mpi": shutil.which("mpicxx") is not None, "kokkos-kernels": KK is not None,
        "cholmod": os.path.exists("/usr/include/suitesparse/cholmod.h"), "cuda": False}
names = [v for v in ("mpi", "kokkos-kernels", "cholmod", "tests") if v in directives["variants"]]
configured = 0
defaults = tuple(bool(directives["variants"][n]) for n in names)
for values in dict.fromkeys([defaults, (True,) * len(names), (False,) * len(names)]):
    variants = dict(directives["variants"], **dict(zip(names, values)), cuda=False)
    missing = [n for n in names if variants[n] and not have.get(n, True)]
    label = " ".join(("+" if variants[n] else "~") + n for n in names)
    if missing:
        print(f"  {label}: left out (this machine lacks {', '.join(missing)})")
        continue
    args = Nacre(Spec(variants)).cmake_args()
    build = os.path.join(WORK, "b" + "".join("1" if v else "0" for v in values))
    shutil.rmtree(build, ignore_errors=True)
    gen = ["-G", "Ninja"] if shutil.which("ninja") else []
    p = subprocess.run(["cmake", "-S", SRC, "-B", build, *gen, "-DCMAKE_BUILD_TYPE=Release", *args],
                       capture_output=True, text=True)
    out = p.stdout + p.stderr
    if p.returncode != 0:
        print(f"FAIL: {label}: cmake {' '.join(args)}\n{out[-3000:]}")
        fails += 1
    elif "Manually-specified variables were not used" in out:
        print(f"FAIL: {label}: options the project does not know:\n{out[out.index('Manually-specified'):][:600]}")
        fails += 1
    else:
        configured += 1
        print(f"  {label}: configured ({' '.join(a for a in args if 'ROOT' not in a and 'COMPILER' not in a)})")
    shutil.rmtree(build, ignore_errors=True)
if configured == 0:
    print("FAIL: no variant combination could be configured")
    fails += 1
print(f"spack recipe: {configured} variant combinations configured, {fails} failure(s)")
sys.exit(1 if fails else 0)
