// barylab — the command line: a thin shell over the pipeline builder (barylabPipeline.h).
//
//   barylab weights --method mvc --cage CAGE --points MODEL --output OUT [--json SUMMARY]
//   barylab weights --method bbw --mesh DOMAIN --handles HANDLES [--points MODEL] --output OUT
//                   [--fast]
//   barylab weights --method lbc --cage CAGE [--mesh DOMAIN | --cells N] [--points MODEL]
//                   --output OUT [--locality squared|constant|linear] [--max-iterations N] ...
//   barylab deform  --method mvc --cage REST --deformed-cage POSED --points MODEL --output OUT
//                   [--weights FILE]
//   barylab deform  --method bbw --mesh DOMAIN --handles HANDLES --points MODEL --output OUT
//                   (--transforms POSE | --deformed-handles POSED [--pseudo-edges FILE])
//                   [--weights FILE] [--fast]
//   barylab stats   --input WEIGHTS_FILE [--cage CAGE] [--json] [--threshold T]
//   barylab stats   --locality --input W1 [--input W2 ...] [--csv PREFIX] [--json]
//                   [--json-output FILE] [--threshold T] [--no-measure]
//   barylab reduce  --input WEIGHTS_FILE [--cage CAGE] --output OUT [--threshold T]
//                   [--renormalize rowsum|affine|none] [--keep-dense] [--json]
//   barylab segment --image LABELMAP [--label K | --threshold T] --output SURFACE
//                   [--smoothing N] [--faces F | --reduction R] [--json SUMMARY]
//   barylab mesh    --cage CAGE [--points MODEL] [--max-volume V | --cells N] --output DOMAIN
//   barylab cage    --model MODEL [--vertices N] [--margin D] --output CAGE [--json SUMMARY]
//   barylab embed   --mesh SURFACE --output E.txt [--dimension D] [--landmarks L]
//   barylab average --mesh SURFACE [--embedding E.txt] --anchors A --weights W --output OUT
//   barylab average --inverse --mesh SURFACE [--embedding E.txt] --anchors A --points Q
//                   --output W.txt
//   barylab curve   --mesh SURFACE [--embedding E.txt] --controls C --output CURVE [--closed]
//   barylab remesh  --mesh SURFACE [--embedding E.txt] --coarse QUADS --output OUT [--levels L]
//   barylab transfer --source A --source-anchors AA --target B --target-anchors BA --output OUT
//                   [--source-embedding EA] [--target-embedding EB] [--morph N --morph-dir DIR]
//   barylab render  --input WEIGHTS_FILE [--cage CAGE] --output PNG [--control I]
//   barylab demo    [--output-dir DIR]
//
// One file per subcommand (barylabCommand<Name>.cxx, registered below in --help order); what
// they share is in barylabCli.h.
//
// Exit codes: 0 success, 1 bad input or failed computation (one line on stderr naming the
// problem), 2 bad command line.
//
// Distributed runs: `mpirun -np K barylab weights|deform|animate ...` (docs/distributed.md):
// every process parses the same command line; process 0 prints what the command line prints,
// the lowest failing process its error.

#include "barylabCli.h"

#include "core/common/error.h"

#include "vtkLogger.h"

#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>
#include <set>
#include <sstream>

int main(int argc, char** argv)
{
  // Problems reach the user as one "barylab: error:" line each (the readers and filters report
  // them as exceptions); VTK's own log lines on stderr would come before it, coloured.
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);

  namespace cli = barylab::cli;
  barylab::DistributedSession session(&argc, &argv); // MPI when started by mpirun
  if (session.MissingMPI())
  {
    std::cerr << "barylab: error: started by an MPI launcher, but this barylab was built "
                 "without MPI (VTK's ParallelMPI module was not found)\n";
    return 1;
  }
  CLI::App app;
  cli::Subcommands subcommands(app);
  cli::ConfigureApp(app, subcommands);
  {
    // every process parses the same command line: process 0 alone prints help and usage errors
    std::ostringstream silent;
    std::streambuf* out = std::cout.rdbuf();
    std::streambuf* err = std::cerr.rdbuf();
    if (barylab::ProcessRank() != 0)
    {
      std::cout.rdbuf(silent.rdbuf());
      std::cerr.rdbuf(silent.rdbuf());
    }
    const int parsed = cli::ParseArguments(app, argc, argv);
    std::cout.rdbuf(out);
    std::cerr.rdbuf(err);
    if (parsed != 0)
      return parsed < 0 ? 0 : parsed;
  }
  if (barylab::Distributed())
  {
    static const std::set<std::string> distributed = { "weights", "deform", "animate" };
    for (const CLI::App* command : app.get_subcommands())
      if (!distributed.count(command->get_name()))
      {
        if (barylab::ProcessRank() == 0)
          std::cerr << "barylab: usage error: '" << command->get_name()
                    << "' runs on one process; distributed runs (mpirun -np K) are for "
                       "weights, deform and animate\n";
        return 2;
      }
  }

  try
  {
    return subcommands.Run();
  }
  catch (const barylab::PeerFailure&)
  {
    return 1; // the failing process printed the error
  }
  catch (const cli::UsageError& e)
  {
    if (barylab::ReportsErrors())
      std::cerr << "barylab: usage error: " << bary::one_line(e.what())
              << "\nRun with --help for more information.\n";
    return 2;
  }
  catch (const bary::Error& e)
  {
    if (barylab::ReportsErrors())
      std::cerr << "barylab: error" << barylab::ProcessLabel() << ": " << e.what() << "\n";
    return 1;
  }
  catch (const std::exception& e)
  {
    if (barylab::ReportsErrors())
      std::cerr << "barylab: error" << barylab::ProcessLabel() << ": " << bary::one_line(e.what())
                << "\n";
    return 1;
  }
}
