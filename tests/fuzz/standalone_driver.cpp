// A main() for the fuzz targets where libFuzzer is not used (gcc, or clang without
// SCREE_FUZZ): it replays a corpus, then runs deterministic pseudo-random mutations of
// it for a given number of inputs or seconds, whichever ends first.
//
//   fuzz_<target> [--seconds S] [--runs N] [--seed K] [--max-len L] [--timeout T]
//                 [--dict foam.dict] CORPUS_DIR_OR_FILE...
//
// Mutations (1 to 4 per input): flip a bit, set a byte, insert or delete bytes, copy a
// range within the input, splice in part of another corpus input, insert a token of the
// dictionary (libFuzzer's -dict format: lines `name="value"`). The seed fixes the whole
// sequence: a run is repeatable, and so is its failure. An input that crashes, aborts
// (the targets abort on a finding) or runs longer than --timeout seconds is written to
// fuzz-<target>-crash.bin in the working directory before the process dies.
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
extern "C" __attribute__((weak)) int LLVMFuzzerInitialize(int* argc, char*** argv);
extern "C" __attribute__((weak)) void __sanitizer_set_death_callback(void (*)(void));

namespace fs = std::filesystem;

namespace {

// The input being run, for the handlers (set before every run).
const std::uint8_t* g_data = nullptr;
std::size_t g_size = 0;
char g_crash_path[512] = "fuzz-crash.bin";

void save_current_input() {
  static volatile sig_atomic_t saved = 0;
  if (saved || !g_data) return;
  saved = 1;
  const int fd = ::open(g_crash_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) {
    std::size_t off = 0;
    while (off < g_size) {
      const ssize_t n = ::write(fd, g_data + off, g_size - off);
      if (n <= 0) break;
      off += static_cast<std::size_t>(n);
    }
    ::close(fd);
  }
  const char msg[] = "\nfuzz driver: the input that failed is in ";
  (void)!::write(2, msg, sizeof msg - 1);
  (void)!::write(2, g_crash_path, std::strlen(g_crash_path));
  (void)!::write(2, "\n", 1);
}

void on_signal(int sig) {
  if (sig == SIGALRM) {
    const char msg[] = "\nfuzz driver: timeout: one input ran longer than --timeout\n";
    (void)!::write(2, msg, sizeof msg - 1);
  }
  save_current_input();
  ::signal(sig == SIGALRM ? SIGABRT : sig, SIG_DFL);
  if (sig == SIGALRM) ::abort();
  ::raise(sig);
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Tokens of a libFuzzer dictionary: `name="value"` or `"value"`, with \\ \" \xNN escapes.
std::vector<std::string> read_dict(const fs::path& p) {
  std::vector<std::string> tokens;
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line)) {
    const auto q = line.find('"');
    const auto e = line.rfind('"');
    if (line.empty() || line[0] == '#' || q == std::string::npos || e <= q) continue;
    std::string t;
    for (std::size_t i = q + 1; i < e; ++i) {
      if (line[i] == '\\' && i + 1 < e) {
        if (line[i + 1] == 'x' && i + 3 < e) {
          t += static_cast<char>(std::stoi(line.substr(i + 2, 2), nullptr, 16));
          i += 3;
        } else {
          t += line[++i];
        }
      } else {
        t += line[i];
      }
    }
    tokens.push_back(t);
  }
  return tokens;
}

void mutate(std::string& s, const std::vector<std::string>& corpus, const std::vector<std::string>& tokens,
            std::mt19937_64& rng, std::size_t max_len) {
  auto pick = [&](std::size_t n) { return n == 0 ? std::size_t{0} : static_cast<std::size_t>(rng() % n); };
  const int count = 1 + static_cast<int>(rng() % 4);
  for (int k = 0; k < count; ++k) {
    switch (rng() % 8) {
      case 0:  // flip a bit
        if (!s.empty()) s[pick(s.size())] ^= static_cast<char>(1u << (rng() % 8));
        break;
      case 1:  // set a byte (often a printable one)
        if (!s.empty()) s[pick(s.size())] = static_cast<char>(rng() % 3 ? 32 + rng() % 95 : rng() % 256);
        break;
      case 2:  // insert bytes
        s.insert(pick(s.size() + 1), std::string(1 + pick(4), static_cast<char>(32 + rng() % 95)));
        break;
      case 3:  // delete a range
        if (!s.empty()) {
          const std::size_t at = pick(s.size());
          s.erase(at, 1 + pick(std::min<std::size_t>(s.size() - at, 16)));
        }
        break;
      case 4:  // copy a range of the input elsewhere in it
        if (!s.empty()) {
          const std::size_t from = pick(s.size());
          const std::string part = s.substr(from, 1 + pick(std::min<std::size_t>(s.size() - from, 64)));
          s.insert(pick(s.size() + 1), part);
        }
        break;
      case 5:  // splice: part of another corpus input
        if (!corpus.empty()) {
          const std::string& o = corpus[pick(corpus.size())];
          if (!o.empty()) {
            const std::size_t from = pick(o.size());
            s.insert(pick(s.size() + 1), o.substr(from, 1 + pick(std::min<std::size_t>(o.size() - from, 128))));
          }
        }
        break;
      default:  // a dictionary token, alone or replacing a few bytes
        if (!tokens.empty()) {
          const std::string& t = tokens[pick(tokens.size())];
          const std::size_t at = pick(s.size() + 1);
          if (rng() % 2 && at < s.size()) s.erase(at, 1 + pick(std::min<std::size_t>(s.size() - at, 8)));
          s.insert(std::min(at, s.size()), t);
        }
        break;
    }
  }
  if (s.size() > max_len) s.resize(max_len);
}

int usage(const char* argv0) {
  std::fprintf(stderr,
               "usage: %s [--seconds S] [--runs N] [--seed K] [--max-len L] [--timeout T] [--dict FILE] "
               "CORPUS_DIR_OR_FILE...\n",
               argv0);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 10;
  long long runs = -1;  // -1: until the time is up
  std::uint64_t seed = 1;
  std::size_t max_len = 16384;
  unsigned timeout = 20;
  std::vector<std::string> tokens;
  std::vector<fs::path> inputs;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) std::exit(usage(argv[0]));
      return argv[++i];
    };
    if (a == "--seconds") seconds = std::stod(value());
    else if (a == "--runs") runs = std::stoll(value());
    else if (a == "--seed") seed = std::stoull(value());
    else if (a == "--max-len") max_len = std::stoull(value());
    else if (a == "--timeout") timeout = static_cast<unsigned>(std::stoul(value()));
    else if (a == "--dict") tokens = read_dict(value());
    else if (a.rfind("--", 0) == 0) return usage(argv[0]);
    else inputs.emplace_back(a);
  }
  const std::string target = fs::path(argv[0]).filename().string();
  std::snprintf(g_crash_path, sizeof g_crash_path, "%s-crash.bin", target.c_str());

  // The corpus, in a fixed order (sorted paths).
  std::vector<fs::path> files;
  for (const fs::path& p : inputs) {
    if (fs::is_directory(p)) {
      for (const auto& e : fs::recursive_directory_iterator(p))
        if (e.is_regular_file()) files.push_back(e.path());
    } else if (fs::is_regular_file(p)) {
      files.push_back(p);
    } else {
      std::fprintf(stderr, "%s: no such corpus file or directory: %s\n", target.c_str(), p.string().c_str());
      return 2;
    }
  }
  std::sort(files.begin(), files.end());
  std::vector<std::string> corpus;
  for (const fs::path& f : files) corpus.push_back(read_file(f));

  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGALRM}) ::signal(sig, on_signal);
  if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(save_current_input);
  if (LLVMFuzzerInitialize) LLVMFuzzerInitialize(&argc, &argv);

  auto run_one = [&](const std::string& s) {
    g_data = reinterpret_cast<const std::uint8_t*>(s.data());
    g_size = s.size();
    ::alarm(timeout);
    LLVMFuzzerTestOneInput(g_data, g_size);
    ::alarm(0);
  };

  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  for (std::size_t i = 0; i < corpus.size(); ++i) {
    std::snprintf(g_crash_path, sizeof g_crash_path, "%s-crash.bin", target.c_str());
    run_one(corpus[i]);
  }
  const double replay = elapsed();
  std::printf("%s: replayed %zu corpus inputs in %.2f s\n", target.c_str(), corpus.size(), replay);
  std::fflush(stdout);

  std::mt19937_64 rng(seed);
  long long done = 0;
  std::string s;
  while ((runs < 0 || done < runs) && elapsed() < seconds) {
    s = corpus.empty() ? std::string() : corpus[rng() % corpus.size()];
    mutate(s, corpus, tokens, rng, max_len);
    run_one(s);
    ++done;
  }
  const double t = elapsed() - replay;
  std::printf("%s: %lld mutated inputs (seed %llu) in %.2f s (%.0f/s), no finding\n", target.c_str(), done,
              static_cast<unsigned long long>(seed), t, t > 0 ? done / t : 0.0);
  return 0;
}
