// Output helpers shared by writers and function objects.
#include "scree/output/writer.hpp"

#include <atomic>
#include <system_error>
#include <unistd.h>

#include "scree/output/function_object.hpp"

namespace scree {

Writer::~Writer() = default;
FunctionObject::~FunctionObject() = default;

namespace {
constexpr const char* kTemporaryMark = ".tmp";  // ".<target>.tmp<pid>_<n>"
}

std::string atomic_temporary_target(const std::string& name) {
  if (name.size() < 2 || name[0] != '.') return {};
  const auto at = name.rfind(kTemporaryMark);
  if (at == std::string::npos || at < 2) return {};
  const std::string tail = name.substr(at + std::char_traits<char>::length(kTemporaryMark));
  const auto us = tail.find('_');
  auto digits = [](const std::string& t) { return !t.empty() && t.find_first_not_of("0123456789") == std::string::npos; };
  if (us == std::string::npos || !digits(tail.substr(0, us)) || !digits(tail.substr(us + 1))) return {};
  return name.substr(1, at - 1);
}

void write_file_atomically(const std::filesystem::path& target,
                           const std::function<void(const std::filesystem::path&)>& fill) {
  static std::atomic<int> counter{0};
  std::filesystem::create_directories(target.parent_path());
  // A hidden temporary in the same directory (so the rename is atomic on one filesystem).
  const auto tmp = target.parent_path() / ("." + target.filename().string() + kTemporaryMark +
                                           std::to_string(::getpid()) + "_" + std::to_string(counter++));
  try {
    fill(tmp);
    std::filesystem::rename(tmp, target);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

}  // namespace scree
