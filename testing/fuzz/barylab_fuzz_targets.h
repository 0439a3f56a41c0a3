#pragma once
/// @file barylab_fuzz_targets.h
/// The fuzz targets: every reader of BaryLab (one per file format, through the same entry point
/// the command line and the viewer use) and the command line's argument parsing. Each target
/// takes the bytes of one input and must either accept it or refuse it with a bary::Error;
/// anything else (a crash, a sanitizer report, another exception, a hang) is a bug.
///
/// Used by the libFuzzer executables (barylab_fuzz_libfuzzer.cxx, clang, -DBARYLAB_FUZZ=ON) and
/// by the mutation driver barylab_fuzz (barylab_fuzz_driver.cxx, any compiler, run by ctest).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace barylab
{
namespace fuzz
{

struct Target
{
  std::string name;      ///< "vtk", "obj", "cli", ...
  std::string extension; ///< of the scratch file the input is written to (".vtk"); "" for cli
  std::string what;      ///< the entry point it exercises, for --list
  /// Runs one input held in @p path (readers) or @p bytes (the command line).
  void (*run)(const std::string& path, const std::uint8_t* bytes, std::size_t size);
  /// Tokens that mutations insert (format keywords, awkward numbers).
  std::vector<std::string> dictionary;
  /// Seeds of its own (the command line's); the readers' are made by Seeds() from data/.
  std::vector<std::string> (*own_seeds)() = nullptr;
};

/// Every target this build has (the command line's only where the app is built).
const std::vector<Target>& Targets();
const Target* FindTarget(const std::string& name);

/// Adds @p target to Targets().
void RegisterTarget(Target target);

/// Registers the command-line target: defined in barylab_fuzz_cli.cxx, which is linked (and
/// BARYLAB_FUZZ_CLI defined) only where the app is built.
void RegisterCliTarget();

/// The seed inputs of @p target, made from the bundled data/ (@p data_dir) through BaryLab's
/// and VTK's writers in each variant of the format (ASCII, binary, compressed, ...).
std::vector<std::string> Seeds(const Target& target, const std::string& data_dir);

/// Runs @p size bytes through @p target: written to a scratch file in @p scratch_dir (readers),
/// then read. bary::Error is the expected refusal and returns false; true when accepted. Any
/// other exception propagates (the harness reports it as a bug).
bool RunOne(const Target& target, const std::string& scratch_dir, const std::uint8_t* bytes,
  std::size_t size);

/// The scratch file RunOne writes for @p target (kept after a crash: the input that caused it).
std::string ScratchPath(const Target& target, const std::string& scratch_dir);

/// VTK's global output window silenced (readers report through it; RunOne's refusals are
/// counted, not printed).
void Quiet();

} // namespace fuzz
} // namespace barylab
