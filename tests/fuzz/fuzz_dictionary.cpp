// Fuzz target: bytes -> Dictionary::parse, as a file of a case would be read.
//
// Every input must end in a Dictionary or in an InputError whose what() begins with
// "file:line:col: " (the file being the parsed one or a file it includes); any other
// exception, a crash, a sanitizer report or a hang is a finding. A dictionary that was
// read is written back (to_string) and read again: the text the writer produces must
// read back to the same text (the writer serves --list-plugins and messages).
//
// The input is parsed as <scratch>/dict, so `#include "inc"` finds the small files
// written into the scratch directory at start: one with entries and a sub-dictionary
// to reach with $macros, one that includes itself, one with a NUL byte, a directory.
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "fuzz_common.hpp"

namespace {

const std::string& dict_path() {
  static const std::string path = [] {
    const auto& dir = scree::fuzz::scratch_dir("dictionary");
    auto write = [&](const char* name, const std::string& text) {
      std::ofstream(dir / name, std::ios::binary) << text;
    };
    write("inc", "a 1;\nsub { b 2; c (1 2 3); d { e word; } }\nl (x \"y\" 3.5);\n");
    write("self", "#include \"self\"\n");
    write("other", "#inputMode overwrite\na 2;\n#include \"inc\"\n");
    write("binary", std::string("a 1;\0b 2;\n", 10));
    std::filesystem::create_directories(dir / "subdir");
    return (dir / "dict").string();
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  (void)dict_path();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string& name = dict_path();
  std::string written;
  try {
    const scree::Dictionary d = scree::Dictionary::parse(text, name);
    written = d.to_string();
  } catch (const scree::InputError& e) {
    scree::fuzz::check_located(e, true);
    return 0;
  } catch (const std::exception& e) {
    scree::fuzz::finding(std::string("an exception other than InputError: ") + e.what());
  } catch (...) {
    scree::fuzz::finding("an exception that is no std::exception");
  }
  // Round trip: what the writer wrote reads back, and is written the same again.
  try {
    const scree::Dictionary again = scree::Dictionary::parse(written, name);
    if (again.to_string() != written)
      scree::fuzz::finding("to_string() does not read back the same:\n--- first\n" + written + "--- second\n" +
                           again.to_string());
  } catch (const scree::InputError& e) {
    scree::fuzz::finding(std::string("to_string() wrote a dictionary that does not read back: ") + e.what() +
                         "\n--- written\n" + written);
  }
  return 0;
}
