// The command line's argument parsing as a fuzz target: the input's bytes, split at NUL and
// newline, are the arguments after "barylab"; they are parsed (ConfigureApp, ParseArguments:
// exactly what main does) but not run. Every outcome is an exit code; a hang (CLI11 2.1.2
// looped forever on weights "" --x), a crash or an exception escaping is a bug.
#include "barylab_fuzz_targets.h"

#include "barylabCli.h"

#include <CLI/CLI.hpp>

namespace barylab
{
namespace fuzz
{
namespace
{
void parse(const std::string&, const std::uint8_t* bytes, std::size_t size)
{
  std::vector<std::string> args{ "barylab" };
  std::string current;
  for (std::size_t i = 0; i < size && args.size() < 64; ++i)
  {
    const char c = static_cast<char>(bytes[i]);
    if (c == '\0' || c == '\n')
    {
      args.push_back(current);
      current.clear();
    }
    else
      current += c;
  }
  if (!current.empty() && args.size() < 64)
    args.push_back(current);
  std::vector<const char*> argv;
  for (const std::string& a : args)
    argv.push_back(a.c_str());
  CLI::App app;
  cli::Subcommands subcommands(app);
  cli::ConfigureApp(app, subcommands);
  cli::ParseArguments(app, static_cast<int>(argv.size()), argv.data(), true);
}

std::string lines(std::initializer_list<const char*> args)
{
  std::string s;
  for (const char* a : args)
    (s += a) += '\n';
  return s;
}
} // namespace

/// The seeds: the command lines of the README and the usage text.
std::vector<std::string> CliSeeds()
{
  return {
    lines({ "weights", "--method", "mvc", "--cage", "data/cage3d.obj", "--points",
      "data/model3d.off", "--output", "w.vtp", "--json", "s.json" }),
    lines({ "weights", "--method", "lbc", "--cage", "c.obj", "--cells", "5000", "--locality",
      "linear", "--max-iterations", "100", "--primal-tolerance", "1e-4", "--output", "w.vtp" }),
    lines({ "weights", "--method", "bbw", "--mesh", "d.mesh", "--handles", "h.tgf", "--fast",
      "--output", "w.vtu" }),
    lines({ "weights", "--method", "scc", "--control-points", "c.obj", "--lambda", "3",
      "--points", "m.off", "--output", "w.vtp", "--threads", "2" }),
    lines({ "deform", "--method", "bbw", "--mesh", "d.mesh", "--handles", "h.tgf", "--points",
      "m.obj", "--transforms", "p.dmat", "--output", "o.vtp" }),
    lines({ "animate", "--method", "scc", "--control-points", "c.obj", "--frames", "f.obj",
      "--points", "m.off", "--output-dir", "out", "--period", "0.5", "--prefix", "beat" }),
    lines({ "stats", "--locality", "--input", "a.vtp", "--input", "b.vtp", "--csv", "p",
      "--threshold", "1e-3" }),
    lines({ "reduce", "--input", "w.vtp", "--cage", "c.obj", "--output", "r.vtp",
      "--renormalize", "affine", "--threshold", "0.01" }),
    lines({ "fields", "--input", "w.vtp", "--level-sets", "l.vtp", "--levels", "0.01,0.05",
      "--control", "36" }),
    lines({ "mesh", "--cage", "c.obj", "--radius-edge-ratio", "1.1", "--min-angle", "20",
      "--output", "m.vtu" }),
    lines({ "render", "--input", "w.vtp", "--output", "w.png", "--size", "640", "--control", "3" }),
    lines({ "demo", "--output-dir", "out" }),
    lines({ "weights", "", "--x" }),
    lines({ "--help" }),
  };
}

void RegisterCliTarget()
{
  RegisterTarget({ "cli", "", "barylab's argument parsing (ConfigureApp + ParseArguments)", parse,
    { "weights", "deform", "animate", "stats", "reduce", "fields", "mesh", "render", "demo",
      "--method", "mvc", "harmonic", "bbw", "tcc", "scc", "lbc", "--cage", "--points",
      "--output", "--json", "--mesh", "--handles", "--cells", "--max-volume", "--outside",
      "nearest", "--locality", "--threads", "--lambda", "--help", "--version", "-h", "--",
      "=", "nan", "inf", "-1", "1e999", "4294967301", "--boundary-tolerance", "--size",
      "--period", "--prefix", "../x", "" },
    CliSeeds });
}

} // namespace fuzz
} // namespace barylab
