#!/usr/bin/env bash
# BaryLab's one entry point on a fresh Debian 12 machine (as root, or with sudo):
#
#   tools/bootstrap.sh demo [--output-dir DIR]   install deps, build, run the demo pipeline
#   tools/bootstrap.sh test                      install deps, build, run the whole test suite
#   tools/bootstrap.sh build                     install deps and build only
#   tools/bootstrap.sh deps                      install deps only
#
# Installs missing Debian packages (idempotent: nothing is installed when all are present),
# configures and builds in build/ (Release), and starts Xvfb itself when there is no display.
# The test command also builds an AddressSanitizer+UBSan tree (build-asan/) and runs the core
# and filter tests there. Environment: JOBS (parallel build jobs, default: cores),
# BARYLAB_SKIP_ASAN=1 (skip the sanitizer pass, for quick local runs).
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
JOBS=${JOBS:-$(nproc)}
PACKAGES=(
  cmake ninja-build g++ pkg-config lld
  libvtk9-dev libvtk9-qt-dev qtbase5-dev libqt5charts5-dev
  libeigen3-dev libcgal-dev libgmp-dev libmpfr-dev libtet1.5-dev libsuitesparse-dev libomp-dev
  libgtest-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev libinsighttoolkit5-dev
  python3-numpy python3-pytest
  xvfb xauth
)

log() { printf '\033[1m[bootstrap]\033[0m %s\n' "$*" >&2; }

install_deps() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    if [ "$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null)" != "installed" ]; then
      missing+=("$p")
    fi
  done
  if [ ${#missing[@]} -eq 0 ]; then
    log "all ${#PACKAGES[@]} Debian packages present"
    return
  fi
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { log "need root (or sudo) to install: ${missing[*]}"; exit 1; }
    sudo="sudo"
  fi
  log "installing ${#missing[@]} missing packages: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

configure_and_build() { # dir, extra cmake args...
  local dir=$1; shift
  local generator=()
  command -v ninja >/dev/null && generator=(-G Ninja)
  if [ ! -f "$dir/CMakeCache.txt" ]; then
    cmake -S "$ROOT" -B "$dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "$@"
  else
    cmake -S "$ROOT" -B "$dir" "$@" >/dev/null
  fi
  cmake --build "$dir" -j "$JOBS"
}

# Runs "$@" with an X display: the current one, or a private Xvfb started here.
with_display() {
  if [ -n "${DISPLAY:-}" ] && { ! command -v xdpyinfo >/dev/null || xdpyinfo >/dev/null 2>&1; }; then
    "$@"
  else
    log "no X display: running under Xvfb"
    xvfb-run -a -s "-screen 0 1280x1024x24" "$@"
  fi
}

cmd=${1:-}
shift || true
case "$cmd" in
  deps)
    install_deps
    ;;
  build)
    install_deps
    configure_and_build "$ROOT/build"
    ;;
  demo)
    install_deps
    configure_and_build "$ROOT/build"
    out="$ROOT/out/demo"
    args=("$@")
    if [ ${#args[@]} -eq 0 ]; then args=(--output-dir "$out"); fi
    with_display "$ROOT/build/bin/barylab" demo "${args[@]}"
    ;;
  test)
    start=$(date +%s)
    install_deps
    configure_and_build "$ROOT/build"
    log "running the test suite (Release)"
    # ctest runs two tests at once and many of them start OpenMP teams as wide as the machine:
    # libgomp's default spin-waiting then burns the other test's cores (the Release pass took
    # 205 s instead of 231 s with passive waiting on 2 cores).
    export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-PASSIVE}
    # A failing test runs once more (until-pass:2): once in a fresh clone's 1,195 tests a render
    # test could not open the private Xvfb ("bad X server connection") and passed when rerun. A
    # test that really fails fails both times and is reported.
    with_display ctest --test-dir "$ROOT/build" --output-on-failure -j "$JOBS" --timeout 600 \
      --repeat until-pass:2
    if [ "${BARYLAB_SKIP_ASAN:-0}" != "1" ]; then
      # gtest's own filter (a sanitizer tree runs each test executable once: testing/CMakeLists.txt)
      SANITIZER_SLOW='-MeanValueCoordinates3D.MatchesQuadratureOfTheDefiningIntegral:MeanValueCoordinates3D.MatchesQuadratureOutside:vtkBaryCoordinatesLBC.BarycentricPropertiesOnTheBundled3DCage:LBC.MatchesAnIndependentPrimalDualSolver:LBC.ConvergedRuleIsCloserToATightSolveThanThePapers:LBC.ResidualBalancingReachesTheSameWeightsInFewerIterations:Backends/SparseCholeskyBackend.BiLaplacianWithLargeSupernodes/*:MixedHandles.PointBoneOpenCageAndRegionInOneCoupledSolve:Catalogue/SurfaceMeshProperties.QualityMeshWithVolumeBound/icosphere320*:Catalogue/SurfaceMeshProperties.SteinerPointsInsideAreInsertedExactly/icosphere320*:Meshes/LocatorProperties.AgreesWithBruteForceOverAllElements/*:vtkBaryCoordinatesLBC.ResultsDoNotDependOnTheThreadCount:BBWOracle.FastModeMatchesLibiglsMatlabActiveSetOnTheKnight:GreenCoordinates.MatchQuadratureOfTheBoundaryIntegrals3D:BundledStarfish.CageIsValidAndEnclosesItsModel:BoxConstrainedQP.FactorizationStrategiesAndBackendsAgree:MeanValueCoordinates3D.BatchKernelMatchesThePerPointCall:Celestial/CelestialBoundary.RandomPointsOnTheHull/*:Backends/SparseCholeskyBackend.SolvesAPoissonProblem/*'
      log "AddressSanitizer + UndefinedBehaviorSanitizer build of core and filter tests"
      # -O1 -g1 (line tables): the sanitizers' stack traces keep file:line and the tree builds in
      # about 7.5 min instead of 10 on 2 cores; the test code itself is compiled with -O0 there
      # (testing/CMakeLists.txt), which halves its compile time. Each test executable runs once, all its
      # tests in one process (~0.25 s of start-up and leak scan each instead of per test); the
      # slowest under the sanitizers (MVC 3D against quadrature, inside and outside: 54 s; LBC's
      # barycentric properties on the bundled 3D cage: 42 s; LBC against an independent
      # primal-dual solver: 18 s; LBC's converged rule against a tight solve, 2.5 s of CPU in Release;
      # LBC's residual balancing against the fixed penalty on a 42-control icosphere, 2-5 s;
      # the three sparse Cholesky backends on a large bi-Laplacian:
      # 34 s) run in the Release pass only (SANITIZER_SLOW): smaller tests exercise the same code
      # paths here. So do TetGen's quality meshes of the 320-face icosphere (27 s), the point
      # locator against brute force over every element (30 s) and LBC's thread-count check (11 s):
      # the same code runs here on the smaller catalogue entries and meshes. The knight against
      # libigl's MATLAB reference (both lumpings, 28 s) and Green coordinates' 3D quadrature
      # (18 s) too: the other BBW and Green tests run here. So do the starfish data's validation
      # (15 s: the cage checks run here on the other bundled cages) and the box-constrained QP's
      # agreement of all factorisations and backends (12.5 s; its other tests run here). So do
      # the 3D MVC batch kernel against the per-point call over the catalogue (27 s; the
      # kernel's path and thread agreement runs here), the celestial boundary sweeps over random
      # hull points (12 s each; the other boundary cases run here) and the three backends on a
      # Poisson problem (11 s each; the backends' other tests run here). Cage generation and the
      # surface family are not built in this tree at all (BARYLAB_WITH_CAGE_GENERATION,
      # BARYLAB_SANITIZE_SURFACE_TESTS: their CGAL units and tests cost minutes here).
      # UBSan's null and alignment checks are left out here (cmake/BaryLabCompilerFlags.cmake:
      # ~35% of the instrumented library's compile time; AddressSanitizer still reports a null
      # dereference).
      configure_and_build "$ROOT/build-asan" -DBARYLAB_SANITIZE=ON -DBARYLAB_BUILD_APP=OFF \
        -DBARYLAB_BUILD_BENCHMARKS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" \
        -DBARYLAB_SANITIZE_UNDEFINED_SKIP=null,alignment
      # The surface family's tests are left out of this tree (BARYLAB_SANITIZE_SURFACE_TESTS, off):
      # CI's time; the Release pass above runs them.
      # libgomp keeps thread pools alive at exit; leaks inside it are not ours
      ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0} \
      UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
      GTEST_FILTER=$SANITIZER_SLOW \
        ctest --test-dir "$ROOT/build-asan" --output-on-failure -j "$JOBS" -L "core|filters" \
          --timeout 900
    fi
    log "all tests passed in $(( $(date +%s) - start )) s"
    ;;
  *)
    sed -n '2,/^set -euo/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'
    exit 2
    ;;
esac
