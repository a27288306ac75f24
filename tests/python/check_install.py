"""ctest python_install: `cmake --install` of the build into a temporary DESTDIR, then `import
vpsim` from there with this interpreter (Debian's /usr/bin/python3 under ctest), run from an
empty directory so that neither the source nor the build tree is on the path. With an install
prefix of /usr/local or /usr it also checks that the package directory is one the interpreter
searches by default (so no PYTHONPATH is needed after `sudo cmake --install build`).

usage: check_install.py CMAKE BUILD_DIR PREFIX PACKAGE_DIR (relative to PREFIX)"""
import os
import subprocess
import sys
import tempfile


def main(cmake, build, prefix, package_dir):
    with tempfile.TemporaryDirectory(prefix="vpsim-install-") as root:
        env = dict(os.environ, DESTDIR=root)
        subprocess.run([cmake, "--install", build], check=True, env=env,
                       stdout=subprocess.DEVNULL)
        site = os.path.join(root + prefix, package_dir)
        files = sorted(os.listdir(os.path.join(site, "vpsim")))
        assert "__init__.py" in files and any(f.startswith("_vpsim") for f in files), files
        code = ("import vpsim, sys; print(vpsim.__file__); "
                "print(vpsim.mie('1.5-0.1i', 10).qext); "
                "print(len(vpsim.components().planners))")
        env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
        env["PYTHONPATH"] = site
        with tempfile.TemporaryDirectory() as empty:
            done = subprocess.run([sys.executable, "-c", code], cwd=empty, env=env,
                                  capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        where, qext, planners = done.stdout.split()
        assert where.startswith(site), f"imported {where}, not the installed {site}"
        assert float(qext) > 0 and int(planners) > 0
    if prefix in ("/usr/local", "/usr"):
        env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
        path = subprocess.run([sys.executable, "-c", "import sys; print('\\n'.join(sys.path))"],
                              env=env, capture_output=True, text=True, check=True).stdout
        target = os.path.join(prefix, package_dir)
        assert target in path.split("\n"), f"{target} is not on {sys.executable}'s sys.path"
    print(f"installed and imported from {prefix}/{package_dir} (through DESTDIR)")


if __name__ == "__main__":
    main(*sys.argv[1:])
