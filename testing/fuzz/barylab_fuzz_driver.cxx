// barylab_fuzz: a mutation fuzzer for BaryLab's readers and command line that any compiler
// builds (GCC in CI, under AddressSanitizer + UBSan), beside the libFuzzer executables that
// clang builds with -DBARYLAB_FUZZ=ON (coverage-guided, for the long runs; tools/fuzz.sh).
//
//   barylab_fuzz list                       the targets
//   barylab_fuzz seeds DIR [TARGET...]      writes the seed corpus, DIR/<target>/seed-N
//   barylab_fuzz run TARGET|all [--runs N] [--seconds S] [--seed K] [--max-len L]
//                [--timeout T] [--crash-dir D]
//                                           N mutated inputs per target (or S seconds, the
//                                           first reached), seeds first
//   barylab_fuzz replay DIR|FILE...         each file once, with the target named by its folder
//                                           (DIR/<target>/...): the regression inputs
//
// A crash, a sanitizer report, an exception other than bary::Error or an input that runs past
// --timeout seconds (default 20) is a bug: the input is saved as D/<target>-<n><ext> (D
// default: the working folder), the problem printed, and the exit code is 1.
#include "barylab_fuzz_targets.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <string>
#include <fcntl.h>
#include <unistd.h>
#include <vector>

extern "C" void __sanitizer_set_death_callback(void (*)(void)) __attribute__((weak));


namespace
{
namespace fs = std::filesystem;
using barylab::fuzz::Target;

// --- what a crash leaves: the input, saved from a signal handler or a death callback ---------
const std::uint8_t* g_input = nullptr;
std::size_t g_size = 0;
char g_crash_path[4096] = "";
char g_target[64] = ""; // a copy: reports at exit come after the targets are destroyed
volatile bool g_running = false; // inside RunOne: the input is alive and the culprit

void save_input_now(const char* why)
{
  if (!g_running)
  {
    // a report after the run (LeakSanitizer at exit): no one input to blame
    const char* parts[] = { "\nbarylab_fuzz: ", why, " after the inputs of target ", g_target,
      " ran (a leak found at exit: replay them one by one to find it)\n" };
    for (const char* p : parts)
      if (write(2, p, std::strlen(p)) < 0)
        break;
    return;
  }
  const int fd = open(g_crash_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0)
  {
    std::size_t done = 0;
    while (done < g_size)
    {
      const ssize_t n = write(fd, g_input + done, g_size - done);
      if (n <= 0)
        break;
      done += static_cast<std::size_t>(n);
    }
    close(fd);
  }
  const char* parts[] = { "\nbarylab_fuzz: ", why, " in target ", g_target, "; input saved as ",
    g_crash_path, "\n" };
  for (const char* p : parts)
    if (write(2, p, std::strlen(p)) < 0)
      break;
}

void on_death()
{
  save_input_now("sanitizer report");
}

void on_signal(int sig)
{
  save_input_now(sig == SIGALRM ? "hang (past --timeout)" : "crash (signal)");
  _exit(1);
}

void install_handlers()
{
  if (__sanitizer_set_death_callback)
    __sanitizer_set_death_callback(on_death);
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  for (int sig : { SIGALRM, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT })
    sigaction(sig, &sa, nullptr);
}

// --- mutations ------------------------------------------------------------------------------
class Mutator
{
public:
  Mutator(const Target& target, std::uint64_t seed)
    : dictionary_(target.dictionary)
    , rng_(seed)
  {
  }

  std::string mutate(const std::string& parent, const std::vector<std::string>& corpus, std::size_t max_len)
  {
    std::string s = parent;
    const int count = 1 + static_cast<int>(below(4));
    for (int i = 0; i < count; ++i)
      once(s, corpus);
    if (s.size() > max_len)
      s.resize(max_len);
    return s;
  }

  std::size_t below(std::size_t n) { return n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_); }

private:
  void once(std::string& s, const std::vector<std::string>& corpus)
  {
    const std::size_t n = s.size();
    switch (below(11))
    {
      case 0: // flip a bit
        if (n)
          s[below(n)] ^= static_cast<char>(1u << below(8));
        break;
      case 1: // an interesting byte
      {
        static const unsigned char bytes[] = { 0, 0xff, 0x7f, 0x80, '\n', ' ', '-', '9', '.', 'e' };
        if (n)
          s[below(n)] = static_cast<char>(bytes[below(sizeof bytes)]);
        break;
      }
      case 2: // delete a range
        if (n)
        {
          const std::size_t at = below(n);
          s.erase(at, 1 + below(std::min<std::size_t>(n - at, below(4) == 0 ? n : 16)));
        }
        break;
      case 3: // insert random bytes
      {
        std::string bytes(1 + below(8), '\0');
        for (char& c : bytes)
          c = static_cast<char>(below(256));
        s.insert(below(n + 1), bytes);
        break;
      }
      case 4: // duplicate a range elsewhere
        if (n)
        {
          const std::size_t at = below(n);
          const std::string piece = s.substr(at, 1 + below(std::min<std::size_t>(n - at, 256)));
          s.insert(below(n + 1), piece);
        }
        break;
      case 5:
      case 6: // a dictionary token
        if (!dictionary_.empty())
          s.insert(below(n + 1), dictionary_[below(dictionary_.size())]);
        break;
      case 7: // replace a number with an awkward one
        replace_number(s);
        break;
      case 8: // splice with another input
        if (!corpus.empty())
        {
          const std::string& other = corpus[below(corpus.size())];
          s = s.substr(0, below(n + 1)) + other.substr(below(other.size() + 1));
        }
        break;
      case 9: // truncate
        if (n)
          s.resize(below(n));
        break;
      case 10: // a binary integer (counts, offsets, sizes of binary formats)
      {
        static const std::uint64_t values[] = { 0, 1, 0x7f, 0x80, 0xff, 0xffff, 0x7fffffff,
          0x80000000, 0xffffffff, 0x100000000ull, 0x7fffffffffffffffull, 0xffffffffffffffffull };
        const std::uint64_t v = values[below(sizeof values / sizeof values[0])];
        const std::size_t width = below(2) ? 4 : 8;
        if (n >= width)
        {
          const std::size_t at = below(n - width + 1);
          const bool big = below(2);
          for (std::size_t k = 0; k < width; ++k)
            s[at + k] = static_cast<char>((v >> (8 * (big ? width - 1 - k : k))) & 0xff);
        }
        break;
      }
    }
  }

  void replace_number(std::string& s)
  {
    static const char* const numbers[] = { "nan", "inf", "-inf", "1e999", "-1", "0",
      "4294967301", "2147483648", "-9223372036854775808", "1e300", "1e-400", "99999999999",
      "65536", "3", "1.5" };
    const auto digit = [](char c) { return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == 'e' || c == '+'; };
    const std::size_t n = s.size();
    if (n == 0)
      return;
    std::size_t at = below(n);
    std::size_t tries = 0;
    while (!(s[at] >= '0' && s[at] <= '9') && tries++ < 64)
      at = below(n);
    if (!(s[at] >= '0' && s[at] <= '9'))
      return;
    std::size_t begin = at, end = at;
    while (begin > 0 && digit(s[begin - 1]))
      --begin;
    while (end < n && digit(s[end]))
      ++end;
    const std::string value = below(3) == 0 ? std::to_string(below(1000)) : numbers[below(sizeof numbers / sizeof numbers[0])];
    s.replace(begin, end - begin, value);
  }

  const std::vector<std::string>& dictionary_;
  std::mt19937_64 rng_;
};

std::string slurp(const fs::path& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string data_dir()
{
  const char* env = std::getenv("BARYLAB_DATA_DIR");
  return env && *env ? env : BARYLAB_DATA_DIR;
}

struct Options
{
  long runs = 1000;
  double seconds = 0; // 0: no limit
  std::uint64_t seed = 1;
  std::size_t max_len = 0; // 0: twice the largest seed, at least 4096
  unsigned timeout = 20;
  std::string crash_dir = ".";
};

/// Runs one input; false (after saving it and printing why) when it is a bug.
bool run_checked(const Target& t, const std::string& scratch, const std::string& input,
  const Options& o, long number, bool& accepted)
{
  g_input = reinterpret_cast<const std::uint8_t*>(input.data());
  g_size = input.size();
  std::snprintf(g_target, sizeof g_target, "%s", t.name.c_str());
  const std::string crash = o.crash_dir + "/" + t.name + "-" + std::to_string(number) +
    (t.extension.empty() ? ".args" : t.extension);
  std::snprintf(g_crash_path, sizeof g_crash_path, "%s", crash.c_str());
  alarm(o.timeout);
  g_running = true;
  try
  {
    accepted = barylab::fuzz::RunOne(t, scratch, g_input, g_size);
    g_running = false;
  }
  catch (const std::exception& e)
  {
    alarm(0);
    save_input_now("an exception other than bary::Error");
    g_running = false;
    std::cerr << "  what(): " << e.what() << "\n";
    return false;
  }
  catch (...)
  {
    alarm(0);
    save_input_now("an unknown exception");
    g_running = false;
    return false;
  }
  alarm(0);
  return true;
}

int run(const std::vector<const Target*>& targets, const Options& o, const std::string& scratch)
{
  for (const Target* t : targets)
  {
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::string> corpus = barylab::fuzz::Seeds(*t, data_dir());
    if (corpus.empty())
    {
      std::cerr << t->name << ": no seeds\n";
      return 1;
    }
    std::size_t max_len = o.max_len;
    if (max_len == 0)
    {
      for (const std::string& s : corpus)
        max_len = std::max(max_len, 2 * s.size());
      max_len = std::max<std::size_t>(max_len, 4096);
    }
    Mutator mutator(*t, o.seed);
    long accepted_count = 0, executed = 0;
    const std::size_t seeds = corpus.size();
    const auto elapsed = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    for (long i = 0; i < static_cast<long>(seeds) + o.runs; ++i)
    {
      if (o.seconds > 0 && elapsed() > o.seconds)
        break;
      const bool seed = i < static_cast<long>(seeds);
      const std::string input = seed ? corpus[static_cast<std::size_t>(i)]
        : mutator.mutate(corpus[mutator.below(corpus.size())], corpus, max_len);
      bool accepted = false;
      if (!run_checked(*t, scratch, input, o, i, accepted))
        return 1;
      ++executed;
      accepted_count += accepted;
      // accepted variants join the corpus (a few), so later mutations start deeper in the format
      if (!seed && accepted && corpus.size() < 2000 && mutator.below(8) == 0)
        corpus.push_back(input);
    }
    const double s = elapsed();
    std::printf("%-13s %8ld inputs (%ld seeds), %ld read, %ld refused, %.1f s, %.0f/s\n",
      t->name.c_str(), executed, static_cast<long>(seeds), accepted_count,
      executed - accepted_count, s, s > 0 ? executed / s : 0.0);
    std::fflush(stdout);
  }
  return 0;
}

int replay(const std::vector<std::string>& paths, const Options& o, const std::string& scratch)
{
  long count = 0;
  for (const std::string& p : paths)
  {
    std::vector<fs::path> files;
    if (fs::is_directory(p))
    {
      for (const auto& e : fs::recursive_directory_iterator(p))
        if (e.is_regular_file() && e.path().filename().string()[0] != '.' &&
          e.path().filename() != "README.md")
          files.push_back(e.path());
    }
    else
      files.emplace_back(p);
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files)
    {
      const std::string name = f.parent_path().filename().string();
      const Target* t = barylab::fuzz::FindTarget(name);
      if (!t)
      {
        std::cerr << "barylab_fuzz: " << f << ": its folder names no target\n";
        return 2;
      }
      const std::string input = slurp(f);
      bool accepted = false;
      if (!run_checked(*t, scratch, input, o, count, accepted))
      {
        std::cerr << "  (regression input " << f.string() << ")\n";
        return 1;
      }
      ++count;
    }
  }
  std::printf("replayed %ld inputs: no crash, hang or sanitizer report\n", count);
  return 0;
}

int usage()
{
  std::cerr << "usage: barylab_fuzz list | seeds DIR [TARGET...] | run TARGET|all [--runs N] "
               "[--seconds S] [--seed K] [--max-len L] [--timeout T] [--crash-dir D] | "
               "replay DIR|FILE...\n";
  return 2;
}
} // namespace

int main(int argc, char** argv)
{
  namespace fuzz = barylab::fuzz;
#ifdef BARYLAB_FUZZ_CLI
  fuzz::RegisterCliTarget();
#endif
  fuzz::Quiet();
  if (argc < 2)
    return usage();
  const std::string command = argv[1];
  if (command == "list")
  {
    for (const Target& t : fuzz::Targets())
      std::printf("%-13s %s\n", t.name.c_str(), t.what.c_str());
    return 0;
  }
  std::vector<std::string> positional;
  Options o;
  for (int i = 2; i < argc; ++i)
  {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc)
        throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    try
    {
      if (a == "--runs")
        o.runs = std::stol(value());
      else if (a == "--seconds")
        o.seconds = std::stod(value());
      else if (a == "--seed")
        o.seed = std::stoull(value());
      else if (a == "--max-len")
        o.max_len = std::stoul(value());
      else if (a == "--timeout")
        o.timeout = static_cast<unsigned>(std::stoul(value()));
      else if (a == "--crash-dir")
        o.crash_dir = value();
      else if (a.rfind("--", 0) == 0)
        return usage();
      else
        positional.push_back(a);
    }
    catch (const std::exception& e)
    {
      std::cerr << "barylab_fuzz: " << a << ": " << e.what() << "\n";
      return 2;
    }
  }
  if (command == "seeds")
  {
    if (positional.empty())
      return usage();
    const fs::path dir = positional[0];
    for (const Target& t : fuzz::Targets())
    {
      if (positional.size() > 1 &&
        std::find(positional.begin() + 1, positional.end(), t.name) == positional.end())
        continue;
      fs::create_directories(dir / t.name);
      int n = 0;
      for (const std::string& s : fuzz::Seeds(t, data_dir()))
        std::ofstream(dir / t.name / ("seed-" + std::to_string(n++) + t.extension), std::ios::binary) << s;
      std::printf("%-13s %d seeds in %s\n", t.name.c_str(), n, (dir / t.name).c_str());
    }
    return 0;
  }
  char scratch_template[] = "/tmp/barylab-fuzz-XXXXXX";
  if (!mkdtemp(scratch_template))
  {
    std::perror("barylab_fuzz: mkdtemp");
    return 2;
  }
  const std::string scratch = scratch_template;
  install_handlers();
  int code = 2;
  if (command == "run")
  {
    std::vector<const Target*> targets;
    if (positional.size() == 1 && positional[0] == "all")
      for (const Target& t : fuzz::Targets())
        targets.push_back(&t);
    else
      for (const std::string& name : positional)
      {
        const Target* t = fuzz::FindTarget(name);
        if (!t)
        {
          std::cerr << "barylab_fuzz: no target '" << name << "' (barylab_fuzz list)\n";
          return 2;
        }
        targets.push_back(t);
      }
    code = targets.empty() ? usage() : run(targets, o, scratch);
  }
  else if (command == "replay")
    code = positional.empty() ? usage() : replay(positional, o, scratch);
  else
    code = usage();
  std::error_code ignored;
  fs::remove_all(scratch, ignored);
  return code;
}
