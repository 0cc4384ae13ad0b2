// Tests of the OpenFOAM-syntax dictionary reader (scree/io/dictionary.hpp): every syntax
// element with values, kinds and exact locations; macros and includes; typed access and
// its messages; writing back (round trip); malformed input, each error checked for its
// exact file, line and column; hostile input (deep nesting, NUL bytes, exponential
// macros, huge files); and a deterministic fuzz test.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "scree/io/dictionary.hpp"

namespace fs = std::filesystem;
using scree::Dictionary;
using scree::Entry;
using scree::InputError;
using scree::InputErrors;
using scree::Item;
using scree::SourceLocation;

namespace {

// ---------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------

Dictionary parse(std::string_view text, std::string name = "test.dict") { return Dictionary::parse(text, name); }

/// Runs `f`, which must throw an InputError, and returns it.
InputError error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "expected an InputError, but nothing was thrown";
  return InputError({}, "<no error>");
}

InputError parse_error(std::string_view text, std::string name = "test.dict") {
  return error_of([&] { parse(text, name); });
}

/// The error is at file:line:col, its message contains `fragment`, and what() is
/// "file:line:col: message".
void check_error(const InputError& e, const std::string& file, int line, int column, const std::string& fragment) {
  ASSERT_TRUE(e.where().file) << e.what();
  EXPECT_EQ(*e.where().file, file) << e.what();
  EXPECT_EQ(e.where().line, line) << e.what();
  if (column > 0) {
    EXPECT_EQ(e.where().column, column) << e.what();
  }
  EXPECT_NE(e.message().find(fragment), std::string::npos) << "message: " << e.message() << "\nwanted: " << fragment;
  EXPECT_EQ(std::string(e.what()), e.where().str() + ": " + e.message());
}

#define EXPECT_PARSE_ERROR(text, line, column, fragment)                   \
  do {                                                                     \
    SCOPED_TRACE(std::string("input: ") + std::string(text));              \
    check_error(parse_error(text), "test.dict", line, column, fragment);   \
  } while (0)

void expect_at(const SourceLocation& where, const std::string& file, int line, int column) {
  ASSERT_TRUE(where.file);
  EXPECT_EQ(*where.file, file);
  EXPECT_EQ(where.line, line);
  EXPECT_EQ(where.column, column);
}

/// A fresh directory under the system temp directory, removed afterwards.
class TempDir {
 public:
  TempDir() {
    static int counter = 0;
    path_ = fs::temp_directory_path() /
            ("scree-test-dictionary-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const fs::path& path() const { return path_; }
  fs::path write(const std::string& relative, std::string_view text) const {
    const fs::path p = path_ / relative;
    fs::create_directories(p.parent_path());
    std::ofstream out(p, std::ios::binary);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    return p;
  }

 private:
  fs::path path_;
};

/// Same structure: keys in order, kinds, values, dictionary names (not locations).
::testing::AssertionResult same(const Dictionary& a, const Dictionary& b, const std::string& at = "");

::testing::AssertionResult same(const Item& a, const Item& b, const std::string& at) {
  if (a.kind() != b.kind()) return ::testing::AssertionFailure() << at << ": kinds differ";
  switch (a.kind()) {
    case Item::Kind::word:
    case Item::Kind::string:
      if (a.text() != b.text()) return ::testing::AssertionFailure() << at << ": '" << a.text() << "' vs '" << b.text() << "'";
      break;
    case Item::Kind::number:
      if (!(a.number() == b.number() || (std::isnan(a.number()) && std::isnan(b.number()))) || a.integral() != b.integral())
        return ::testing::AssertionFailure() << at << ": " << a.number() << " vs " << b.number();
      break;
    case Item::Kind::list:
      if (a.list().size() != b.list().size()) return ::testing::AssertionFailure() << at << ": list sizes differ";
      for (std::size_t i = 0; i < a.list().size(); ++i)
        if (auto r = same(a.list()[i], b.list()[i], at + "[" + std::to_string(i) + "]"); !r) return r;
      break;
    case Item::Kind::dict:
      if (!a.dict() || !b.dict()) return ::testing::AssertionFailure() << at << ": null dictionary";
      return same(*a.dict(), *b.dict(), at);
  }
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult same(const Dictionary& a, const Dictionary& b, const std::string& at) {
  if (a.name() != b.name())
    return ::testing::AssertionFailure() << at << ": names '" << a.name() << "' vs '" << b.name() << "'";
  if (a.entries().size() != b.entries().size())
    return ::testing::AssertionFailure() << at << ": " << a.entries().size() << " vs " << b.entries().size()
                                         << " entries";
  if ((a.header() == nullptr) != (b.header() == nullptr))
    return ::testing::AssertionFailure() << at << ": header present in only one";
  if (a.header())
    if (auto r = same(*a.header(), *b.header(), at + "/FoamFile"); !r) return r;
  for (std::size_t i = 0; i < a.entries().size(); ++i) {
    const Entry& x = a.entries()[i];
    const Entry& y = b.entries()[i];
    const std::string here = at + "/" + x.key();
    if (x.key() != y.key()) return ::testing::AssertionFailure() << here << ": key vs '" << y.key() << "'";
    if (x.is_dict() != y.is_dict()) return ::testing::AssertionFailure() << here << ": dict vs primitive";
    if (x.is_dict()) {
      if (auto r = same(x.dict(), y.dict(), here); !r) return r;
      continue;
    }
    if (x.items().size() != y.items().size()) return ::testing::AssertionFailure() << here << ": item counts differ";
    for (std::size_t k = 0; k < x.items().size(); ++k)
      if (auto r = same(x.items()[k], y.items()[k], here + "#" + std::to_string(k)); !r) return r;
  }
  return ::testing::AssertionSuccess();
}

/// parse(to_string(d)) has the same structure as d.
::testing::AssertionResult round_trips(const Dictionary& d) {
  const std::string text = d.to_string();
  try {
    Dictionary again = Dictionary::parse(text, d.name());
    auto r = same(d, again);
    if (!r) r << "\nwritten:\n" << text;
    return r;
  } catch (const InputError& e) {
    return ::testing::AssertionFailure() << "to_string() output does not parse: " << e.what() << "\n" << text;
  }
}

const char* const kControlDict = R"(/*--------------------------------*- C++ -*----------------------------------*\
  Scree case dictionary
\*---------------------------------------------------------------------------*/
FoamFile
{
    version     2.0;
    format      ascii;
    class       dictionary;
    object      controlDict;
}

application     scree;      // the solver
startTime       0;
endTime         1.5;
deltaT          1e-5;
writeInterval   100;
gravity         (0 -9.81);
adaptive        yes;
title           "Column \"collapse\"";

materials
{
    sand
    {
        type    mohrCoulomb;
        rho     2650;
        phi     30;
    }
}
)";

// ---------------------------------------------------------------------------------------
// Locations and error types
// ---------------------------------------------------------------------------------------

TEST(SourceLocation, Str) {
  SourceLocation loc;
  EXPECT_EQ(loc.str(), "<unknown>");
  loc.file = std::make_shared<const std::string>("system/controlDict");
  EXPECT_EQ(loc.str(), "system/controlDict");
  loc.line = 12;
  EXPECT_EQ(loc.str(), "system/controlDict:12");
  loc.column = 5;
  EXPECT_EQ(loc.str(), "system/controlDict:12:5");
}

TEST(InputError, WhatHasLocationThenMessage) {
  InputError e({std::make_shared<const std::string>("a.dict"), 3, 7}, "something is wrong");
  EXPECT_STREQ(e.what(), "a.dict:3:7: something is wrong");
  EXPECT_EQ(e.message(), "something is wrong");
  EXPECT_EQ(e.where().line, 3);
  EXPECT_EQ(e.where().column, 7);
  // Without a location (dictionaries built in code) the message stands alone.
  EXPECT_STREQ(InputError({}, "plain").what(), "plain");
  std::runtime_error& base = e;  // usable as a std::runtime_error
  EXPECT_NE(std::string(base.what()).find("wrong"), std::string::npos);
}

TEST(InputErrors, WhatListsEachErrorOnItsOwnLine) {
  auto f = std::make_shared<const std::string>("f");
  InputErrors errs({InputError({f, 1, 2}, "first"), InputError({f, 3, 4}, "second")});
  EXPECT_STREQ(errs.what(), "f:1:2: first\nf:3:4: second");
  ASSERT_EQ(errs.errors().size(), 2u);
  EXPECT_EQ(errs.errors()[1].message(), "second");
}

// ---------------------------------------------------------------------------------------
// Syntax: values and kinds
// ---------------------------------------------------------------------------------------

TEST(DictionaryParse, TypicalFileWithHeaderValuesAndLocations) {
  Dictionary d = parse(kControlDict, "system/controlDict");
  EXPECT_EQ(d.name(), "system/controlDict");
  ASSERT_NE(d.header(), nullptr);
  EXPECT_EQ(d.header()->get_word("object"), "controlDict");
  EXPECT_DOUBLE_EQ(d.header()->get_scalar("version"), 2.0);
  EXPECT_FALSE(d.has("FoamFile"));  // the header is not an entry
  EXPECT_EQ(d.keys(), (std::vector<std::string>{"application", "startTime", "endTime", "deltaT", "writeInterval",
                                                "gravity", "adaptive", "title", "materials"}));
  EXPECT_EQ(d.get_word("application"), "scree");
  EXPECT_DOUBLE_EQ(d.get_scalar("endTime"), 1.5);
  EXPECT_DOUBLE_EQ(d.get_scalar("deltaT"), 1e-5);
  EXPECT_EQ(d.get_integer("writeInterval"), 100);
  EXPECT_EQ(d.at("gravity").as_scalar_list(), (std::vector<double>{0.0, -9.81}));
  EXPECT_TRUE(d.get_bool("adaptive"));
  EXPECT_EQ(d.get_word("title"), "Column \"collapse\"");

  // Exact locations of entries and items.
  expect_at(d.at("application").where(), "system/controlDict", 12, 1);
  expect_at(d.at("endTime").where(), "system/controlDict", 14, 1);
  expect_at(d.at("endTime").single_item().where(), "system/controlDict", 14, 17);
  const Item& g = d.at("gravity").single_item();
  expect_at(g.where(), "system/controlDict", 17, 17);
  expect_at(g.list()[1].where(), "system/controlDict", 17, 20);
  const Dictionary& sand = d.sub("materials").sub("sand");
  EXPECT_EQ(d.sub("materials").name(), "materials");
  EXPECT_EQ(sand.name(), "materials.sand");
  expect_at(sand.where(), "system/controlDict", 23, 5);
  expect_at(sand.at("rho").where(), "system/controlDict", 26, 9);
  expect_at(sand.at("rho").single_item().where(), "system/controlDict", 26, 17);
  expect_at(d.where(), "system/controlDict", 0, 0);
}

TEST(DictionaryParse, Numbers) {
  Dictionary d = parse(
      "a 42; b -9.81; c 1e-5; d +3; e .5; f 2.; g -0; h 1E+3; i 6.02e23; j -.25e-2; k 007; l 1e-400;"
      "m 9223372036854775807;");
  struct Case {
    const char* key;
    double value;
    bool integral;
    const char* text;
  };
  for (const Case& c : {Case{"a", 42, true, "42"}, Case{"b", -9.81, false, "-9.81"}, Case{"c", 1e-5, false, "1e-5"},
                        Case{"d", 3, true, "+3"}, Case{"e", 0.5, false, ".5"}, Case{"f", 2, false, "2."},
                        Case{"g", 0, true, "-0"}, Case{"h", 1000, false, "1E+3"}, Case{"i", 6.02e23, false, "6.02e23"},
                        Case{"j", -0.0025, false, "-.25e-2"}, Case{"k", 7, true, "007"}, Case{"l", 0, false, "1e-400"}}) {
    SCOPED_TRACE(c.key);
    const Item& it = d.at(c.key).single_item();
    EXPECT_EQ(it.kind(), Item::Kind::number);
    EXPECT_DOUBLE_EQ(it.number(), c.value);
    EXPECT_EQ(it.integral(), c.integral);
    EXPECT_EQ(it.text(), c.text);
    EXPECT_EQ(it.kind_name(), "a number");
  }
  EXPECT_EQ(d.get_integer("m"), std::numeric_limits<long long>::max());  // exact, not via double
  EXPECT_EQ(d.get_integer("d"), 3);
}

TEST(DictionaryParse, WordsAreGenerous) {
  Dictionary d = parse(
      "a linearElastic; b _private; c a.b:c-d+e/f<g>,h; d uniform; e -; f +x; g ..; h /abs/path.so; i x*y; "
      "j 'quoted'; k caf\xC3\xA9; l a#b;");
  const std::vector<std::pair<const char*, const char*>> expected = {
      {"a", "linearElastic"}, {"b", "_private"}, {"c", "a.b:c-d+e/f<g>,h"}, {"d", "uniform"},
      {"e", "-"},             {"f", "+x"},       {"g", ".."},               {"h", "/abs/path.so"},
      {"i", "x*y"},           {"j", "'quoted'"}, {"k", "caf\xC3\xA9"},     {"l", "a#b"}};
  for (const auto& [key, word] : expected) {
    SCOPED_TRACE(key);
    const Item& it = d.at(key).single_item();
    EXPECT_EQ(it.kind(), Item::Kind::word);
    EXPECT_EQ(it.text(), word);
  }
  // Words stop at the delimiters ; ( ) { } " $ and at comments.
  Dictionary e = parse("a x(y)z; b p\"q\"; c w// comment\n; d u/*c*/v;");
  ASSERT_EQ(e.at("a").items().size(), 3u);
  EXPECT_EQ(e.at("a").items()[0].text(), "x");
  EXPECT_EQ(e.at("a").items()[1].kind(), Item::Kind::list);
  EXPECT_EQ(e.at("a").items()[2].text(), "z");
  ASSERT_EQ(e.at("b").items().size(), 2u);
  EXPECT_EQ(e.at("b").items()[1].kind(), Item::Kind::string);
  EXPECT_EQ(e.get_word("c"), "w");
  ASSERT_EQ(e.at("d").items().size(), 2u);
}

TEST(DictionaryParse, Strings) {
  Dictionary d = parse(R"(a "hello world"; b "say \"hi\""; c "back\\slash"; d ""; e "a\tb\n"; f "semi;{}()$#//";)"
                       "\ng \"con\\\ntinued\";");
  EXPECT_EQ(d.get_word("a"), "hello world");
  EXPECT_EQ(d.get_word("b"), "say \"hi\"");
  EXPECT_EQ(d.get_word("c"), "back\\slash");
  EXPECT_EQ(d.get_word("d"), "");
  EXPECT_EQ(d.get_word("e"), "a\\tb\\n");  // other escapes are kept as written
  EXPECT_EQ(d.get_word("f"), "semi;{}()$#//");
  EXPECT_EQ(d.get_word("g"), "continued");  // backslash-newline continues the string
  EXPECT_EQ(d.at("a").single_item().kind(), Item::Kind::string);
  EXPECT_EQ(d.at("b").single_item().to_string(), R"("say \"hi\"")");
  EXPECT_EQ(d.at("c").single_item().to_string(), R"("back\\slash")");
  // Quoted keys are keys.
  EXPECT_EQ(parse(R"("my key" 1;)").get_integer("my key"), 1);
}

TEST(DictionaryParse, MultipleItemsListsAndNesting) {
  Dictionary d = parse(
      "region box (0 0) (1 1.5);\n"
      "mixed ( 1 2.5 word \"str\" (0 1) ((a) ()) );\n"
      "empty ();\n"
      "functions ( { type probe; at (0 1); } { type energy; } );\n");
  const Entry& region = d.at("region");
  ASSERT_EQ(region.items().size(), 3u);
  EXPECT_EQ(region.items()[0].text(), "box");
  EXPECT_EQ(region.items()[2].list()[1].number(), 1.5);
  EXPECT_EQ(region.value_string(), "box (0 0) (1 1.5)");
  EXPECT_THROW(region.single_item(), InputError);

  const Item& mixed = d.at("mixed").single_item();
  ASSERT_EQ(mixed.kind(), Item::Kind::list);
  ASSERT_EQ(mixed.list().size(), 6u);
  EXPECT_EQ(mixed.list()[0].kind(), Item::Kind::number);
  EXPECT_EQ(mixed.list()[2].kind(), Item::Kind::word);
  EXPECT_EQ(mixed.list()[3].kind(), Item::Kind::string);
  EXPECT_EQ(mixed.list()[4].kind(), Item::Kind::list);
  EXPECT_EQ(mixed.list()[5].list()[0].list()[0].text(), "a");
  EXPECT_TRUE(mixed.list()[5].list()[1].list().empty());
  EXPECT_EQ(mixed.kind_name(), "a list");
  EXPECT_TRUE(d.at("empty").as_scalar_list().empty());

  const Item& fns = d.at("functions").single_item();
  ASSERT_EQ(fns.list().size(), 2u);
  ASSERT_EQ(fns.list()[0].kind(), Item::Kind::dict);
  EXPECT_EQ(fns.list()[0].kind_name(), "a dictionary");
  EXPECT_EQ(fns.list()[0].dict()->get_word("type"), "probe");
  EXPECT_EQ(fns.list()[0].dict()->name(), "functions[0]");
  EXPECT_EQ(fns.list()[1].dict()->name(), "functions[1]");
  expect_at(fns.list()[1].where(), "test.dict", 4, 39);
  EXPECT_EQ(fns.to_string(), "({ type probe; at (0 1); } { type energy; })");
}

TEST(DictionaryParse, BooleansAreWords) {
  Dictionary d = parse("a true; b false; c yes; d no; e on; f off; g True; h 1; i \"true\";");
  EXPECT_TRUE(d.get_bool("a"));
  EXPECT_FALSE(d.get_bool("b"));
  EXPECT_TRUE(d.get_bool("c"));
  EXPECT_FALSE(d.get_bool("d"));
  EXPECT_TRUE(d.get_bool("e"));
  EXPECT_FALSE(d.get_bool("f"));
  EXPECT_EQ(d.at("a").single_item().kind(), Item::Kind::word);
  for (const char* bad : {"g", "h", "i"}) EXPECT_THROW(d.get_bool(bad), InputError) << bad;  // case-sensitive
}

TEST(DictionaryParse, SubDictionariesHaveDottedNames) {
  Dictionary d = parse("a { b { c { x 1; } } d 2; } e { };");
  EXPECT_EQ(d.sub("a").name(), "a");
  EXPECT_EQ(d.sub("a").sub("b").name(), "a.b");
  EXPECT_EQ(d.sub("a").sub("b").sub("c").name(), "a.b.c");
  EXPECT_EQ(d.sub("a").sub("b").sub("c").get_integer("x"), 1);
  EXPECT_TRUE(d.sub("e").entries().empty());  // `};` is tolerated
  EXPECT_TRUE(d.at("a").is_dict());
  EXPECT_TRUE(d.at("a").items().empty());
}

TEST(DictionaryParse, CommentsAnywhereWhitespaceMayAppear) {
  Dictionary d = parse(
      "// leading\n"
      "/* block\n   over lines */ a /* between */ 1 /* before ; */ ; // trailing\n"
      "b/**/(1/**/2 // inside a list\n 3);\n"
      "c { /* empty */ }\n"
      "d 4; // no newline at the end");
  EXPECT_EQ(d.get_integer("a"), 1);
  EXPECT_EQ(d.at("b").as_scalar_list(), (std::vector<double>{1, 2, 3}));
  EXPECT_TRUE(d.sub("c").entries().empty());
  EXPECT_EQ(d.get_integer("d"), 4);
  expect_at(d.at("a").where(), "test.dict", 3, 18);
  expect_at(d.at("b").where(), "test.dict", 4, 1);
  expect_at(d.at("b").single_item().list()[2].where(), "test.dict", 5, 2);
}

TEST(DictionaryParse, LineEndingsEmptyInputAndEncoding) {
  Dictionary crlf = parse("a 1;\r\nb\r\n{\r\n    c 2;\r\n}\r\nd \"x\";\r\n");
  EXPECT_EQ(crlf.get_integer("a"), 1);
  EXPECT_EQ(crlf.sub("b").get_integer("c"), 2);
  EXPECT_EQ(crlf.get_word("d"), "x");
  expect_at(crlf.sub("b").at("c").where(), "test.dict", 4, 5);

  EXPECT_TRUE(parse("").entries().empty());
  EXPECT_TRUE(parse("   \n\t\n").entries().empty());
  EXPECT_TRUE(parse("// only a comment").entries().empty());
  EXPECT_TRUE(parse("/* only a comment */").entries().empty());
  EXPECT_EQ(parse("a 1;").get_integer("a"), 1);  // no trailing newline

  // A UTF-8 byte order mark is skipped; columns count characters, not bytes.
  Dictionary bom = parse("\xEF\xBB\xBF" "a 1;\n\xC3\xA9t\xC3\xA9 2; x 3;");
  expect_at(bom.at("a").where(), "test.dict", 1, 1);
  expect_at(bom.at("x").where(), "test.dict", 2, 8);
  // Tabs count as one column.
  expect_at(parse("\ta\t1;").at("a").single_item().where(), "test.dict", 1, 4);
}

// A byte order mark is skipped at the start of the file only. Elsewhere (two files
// joined with cat) it made an invisible part of a word: "\uFEFFFoamFile" was a key
// that printed as 'FoamFile', and the writer wrote it first in its output, where reading
// it back skipped it (found by fuzz_dictionary's round trip). In a string it is kept.
TEST(DictionaryParse, ByteOrderMarkInsideTheFileIsAnError) {
  EXPECT_PARSE_ERROR("a 1;\n\xEF\xBB\xBF" "FoamFile { version 2.0; }\n", 2, 1, "U+FEFF");
  EXPECT_PARSE_ERROR("a b\xEF\xBB\xBF" "c;", 1, 4, "byte order mark");
  EXPECT_PARSE_ERROR("a $b\xEF\xBB\xBF;", 1, 5, "byte order mark");
  EXPECT_PARSE_ERROR("\xEF\xBB\xBF\xEF\xBB\xBF" "a 1;", 1, 1, "byte order mark");
  EXPECT_EQ(parse("a \"x\xEF\xBB\xBFy\";").get_word("a"), "x\xEF\xBB\xBFy");
  const Dictionary d = parse("\xEF\xBB\xBF" "a \"\xEF\xBB\xBF\";");
  EXPECT_EQ(parse(d.to_string()).to_string(), d.to_string());
}

// A key set twice by one file is a mistake (a value appended to a controlDict that
// already sets it, a line copied and not renamed): the second used to replace the first
// silently. The error is at the second and names the first.
TEST(DictionaryParse, DuplicateKeyIsAnErrorNamingBothLines) {
  check_error(parse_error("endTime 3;\ndeltaT 1e-3;\nendTime 1e9;\n", "system/controlDict"), "system/controlDict", 3,
              1, "endTime: duplicate entry, already set at system/controlDict:1:1");
  // In a sub-dictionary, and between a dictionary and a value.
  check_error(parse_error("w\n{\n    p { type vtk; }\n    p { type vtk; }\n}\n"), "test.dict", 4, 5,
              "p: duplicate entry, already set at test.dict:3:5");
  check_error(parse_error("b 2;\nb { x 1; }\n"), "test.dict", 2, 1, "b: duplicate entry, already set at test.dict:1:1");
  // The same key in different dictionaries is no duplicate.
  Dictionary d = parse("a 1;\ns { a 2; t { a 3; } }\n");
  EXPECT_EQ(d.sub("s").sub("t").get_integer("a"), 3);
}

TEST(DictionaryParse, InputModeOverwriteReplacesKeepingFirstPosition) {
  Dictionary d = parse("a 1;\nb 2;\n#inputMode overwrite\na 3;\nb { x 1; }\n");
  EXPECT_EQ(d.keys(), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(d.get_integer("a"), 3);
  expect_at(d.at("a").where(), "test.dict", 4, 1);  // the location of the winner
  EXPECT_TRUE(d.at("b").is_dict());
  expect_at(d.at("b").where(), "test.dict", 5, 1);
  // merge replaces too (sub-dictionaries whole); error is the default again.
  EXPECT_EQ(parse("#inputMode merge\na 1;\n#inputMode overwrite;\na 2;").get_integer("a"), 2);
  check_error(parse_error("#inputMode overwrite\na 1;\na 2;\n#inputMode error\na 3;"), "test.dict", 5, 1,
              "a: duplicate entry, already set at test.dict:3:1");
}

// A variant case includes its base case's file and changes a few entries (the case
// variants under cases/ do: `#include "../../../system/gridDict"` then `cellSize 0.01;`).
// An included or merged entry may be replaced; a key repeated inside one included file
// is still an error, reported in that file.
TEST(DictionaryInclude, AnIncludedOrMergedEntryMayBeReplaced) {
  TempDir dir;
  dir.write("base/gridDict", "dimension 2;\ncellSize 0.02;\n");
  const fs::path variant = dir.write("variant/gridDict", "#include \"../base/gridDict\"\ncellSize 0.01;\n");
  Dictionary d = Dictionary::read_file(variant, "variant/gridDict");
  EXPECT_DOUBLE_EQ(d.get_scalar("cellSize"), 0.01);
  expect_at(d.at("cellSize").where(), "variant/gridDict", 2, 1);
  // Twice after the include is still twice in one file.
  const fs::path twice = dir.write("twice/gridDict", "#include \"../base/gridDict\"\ncellSize 0.01;\ncellSize 0.005;\n");
  check_error(error_of([&] { Dictionary::read_file(twice, "twice/gridDict"); }), "twice/gridDict", 3, 1,
              "cellSize: duplicate entry, already set at twice/gridDict:2:1");
  // Inside the included file.
  dir.write("bad/base", "a 1;\na 2;\n");
  const fs::path includer = dir.write("bad/includer", "#include \"base\"\n");
  check_error(error_of([&] { Dictionary::read_file(includer, "bad/includer"); }), "bad/base", 2, 1,
              "a: duplicate entry, already set at bad/base:1:1");
  // '#inputMode overwrite' of an includer does not reach into the included file.
  const fs::path quiet = dir.write("bad/quiet", "#inputMode overwrite\n#include \"base\"\n");
  EXPECT_THROW(Dictionary::read_file(quiet, "bad/quiet"), InputError);
  // `$name;` merges defaults that the dictionary then changes.
  Dictionary m = parse("sand { rho 2650; E 1e7; }\nwet { $sand; rho 2000; }\n");
  EXPECT_EQ(m.sub("wet").get_integer("rho"), 2000);
}

// ---------------------------------------------------------------------------------------
// Macros
// ---------------------------------------------------------------------------------------

TEST(DictionaryMacros, ValueCopiesAndScopes) {
  Dictionary d = parse(
      "rho 2650;\n"
      "pair 1 2;\n"
      "v (0 -9.81);\n"
      "a $rho;\n"
      "b $pair;\n"
      "c ( $pair 3 $v );\n"
      "d ${rho};\n"
      "e $v;\n"
      "outer\n"
      "{\n"
      "    rho 1000;\n"
      "    inner { x $rho; y $pair; }\n"  // innermost definition wins, then enclosing scopes
      "    z $:rho;\n"                    // `$:` starts at the top level
      "}\n");
  EXPECT_EQ(d.get_integer("a"), 2650);
  EXPECT_EQ(d.at("b").value_string(), "1 2");
  EXPECT_EQ(d.at("c").value_string(), "(1 2 3 (0 -9.81))");
  EXPECT_EQ(d.get_integer("d"), 2650);
  EXPECT_EQ(d.at("e").as_scalar_list(), (std::vector<double>{0, -9.81}));
  EXPECT_EQ(d.sub("outer").sub("inner").get_integer("x"), 1000);
  EXPECT_EQ(d.sub("outer").sub("inner").at("y").value_string(), "1 2");
  EXPECT_EQ(d.sub("outer").get_integer("z"), 2650);
  // Copied items keep the location where the value was written.
  expect_at(d.at("a").single_item().where(), "test.dict", 1, 5);
  expect_at(d.at("a").where(), "test.dict", 4, 1);
}

TEST(DictionaryMacros, OnlyEntriesDefinedBeforeTheUseAreSeen) {
  Dictionary d = parse("x 1;\ns { y $x; x 2; z $x; }\nw $x;");
  EXPECT_EQ(d.sub("s").get_integer("y"), 1);  // s.x is not defined yet
  EXPECT_EQ(d.sub("s").get_integer("z"), 2);
  EXPECT_EQ(d.get_integer("w"), 1);
  check_error(parse_error("a $b;\nb 1;"), "test.dict", 1, 3, "unknown macro '$b' (no entry 'b' in scope)");
  // An entry cannot refer to itself while it is being defined.
  check_error(parse_error("s { t $s; }"), "test.dict", 1, 7, "unknown macro '$s'");
}

TEST(DictionaryMacros, ScopedNamesWalkSubDictionaries) {
  Dictionary d = parse(
      "materials { sand { rho 2650; props { E 1e7; } } }\n"
      "a $materials.sand.rho;\n"
      "b $materials.sand.props.E;\n"
      "c ${materials.sand.rho};\n"
      "c2 ${:materials.sand.props.E};\n"
      "s { materials { other 1; } d $:materials.sand.rho; }\n"
      "\"lit.key\" 5; e $lit.key;\n");
  EXPECT_EQ(d.get_integer("a"), 2650);
  EXPECT_DOUBLE_EQ(d.get_scalar("b"), 1e7);
  EXPECT_EQ(d.get_integer("c"), 2650);
  EXPECT_DOUBLE_EQ(d.get_scalar("c2"), 1e7);
  EXPECT_EQ(d.sub("s").get_integer("d"), 2650);
  EXPECT_EQ(d.get_integer("e"), 5);  // a key containing dots, when no scoped match exists
  // The walk starts from the first match of the first component (no fallback outwards).
  check_error(parse_error("a { x 1; }\ns { a { y 2; } b $a.x; }"), "test.dict", 2, 18,
              "unknown macro '$a.x' (dictionary 'a' has no entry 'x')");
}

TEST(DictionaryMacros, DictionaryCopyAndMerge) {
  Dictionary d = parse(
      "materials\n"
      "{\n"
      "    sand { type mohrCoulomb; rho 2650; }\n"
      "    sand2 $sand;\n"
      "    wet { $sand; rho 2000; extra { $sand; } }\n"
      "}\n"
      "list ( $materials.sand 1 );\n");
  const Dictionary& mats = d.sub("materials");
  const Dictionary& sand2 = mats.sub("sand2");
  EXPECT_EQ(sand2.name(), "materials.sand2");
  EXPECT_EQ(sand2.get_word("type"), "mohrCoulomb");
  expect_at(sand2.where(), "test.dict", 4, 5);
  const Dictionary& wet = mats.sub("wet");
  EXPECT_EQ(wet.keys(), (std::vector<std::string>{"type", "rho", "extra"}));
  EXPECT_EQ(wet.get_integer("rho"), 2000);  // a later entry overrides a merged one
  EXPECT_EQ(wet.sub("extra").get_integer("rho"), 2650);
  EXPECT_EQ(wet.sub("extra").name(), "materials.wet.extra");
  const Item& first = d.at("list").single_item().list()[0];
  ASSERT_EQ(first.kind(), Item::Kind::dict);
  EXPECT_EQ(first.dict()->get_integer("rho"), 2650);
  EXPECT_EQ(first.dict()->name(), "list[0]");
  EXPECT_TRUE(round_trips(d));
}

TEST(DictionaryMacros, ValuesContainingMacrosWereAlreadyExpanded) {
  Dictionary d =
      parse("a 1;\nb $a;\nc $b;\nd { x $c; y ($a $b); }\ne $d;\nf $e.y;\n#inputMode overwrite\na 99;\ng $c;");
  EXPECT_EQ(d.get_integer("c"), 1);
  EXPECT_EQ(d.sub("e").get_integer("x"), 1);
  EXPECT_EQ(d.at("f").as_scalar_list(), (std::vector<double>{1, 1}));
  EXPECT_EQ(d.get_integer("g"), 1);  // redefining a later does not change c
  EXPECT_EQ(d.get_integer("a"), 99);
}

// ---------------------------------------------------------------------------------------
// Includes
// ---------------------------------------------------------------------------------------

TEST(DictionaryInclude, MergesEntriesAtThePointOfInclusion) {
  TempDir dir;
  dir.write("case/system/materials", "// shared\nrho 2650;\nsand\n{\n    E $base;\n}\nrho2 $rho;\n");
  dir.write("case/system/sub/nested.dict", "deep 1;\n#include \"../more\"\n");
  dir.write("case/system/more", "FoamFile { object more; }\nmore $deep;\n");
  const fs::path main = dir.write("case/system/controlDict",
                                  "base 1e7;\n"
                                  "rho 1;\n"
                                  "#include \"materials\"\n"
                                  "after $rho2;\n"
                                  "block\n"
                                  "{\n"
                                  "    #include \"sub/nested.dict\";\n"
                                  "}\n");
  Dictionary d = Dictionary::read_file(main, "system/controlDict");
  EXPECT_EQ(d.name(), "system/controlDict");
  EXPECT_EQ(d.keys(), (std::vector<std::string>{"base", "rho", "sand", "rho2", "after", "block"}));
  EXPECT_EQ(d.get_integer("rho"), 2650);  // replaced by the included value
  EXPECT_DOUBLE_EQ(d.sub("sand").get_scalar("E"), 1e7);  // macros see the includer's entries
  EXPECT_EQ(d.get_integer("after"), 2650);                // and the includer sees the included ones
  EXPECT_EQ(d.sub("block").get_integer("deep"), 1);
  EXPECT_EQ(d.sub("block").get_integer("more"), 1);
  EXPECT_EQ(d.header(), nullptr);  // an included file's header is ignored

  // Locations name the file the entry was read from (relative to the includer's name).
  expect_at(d.at("rho").where(), "system/materials", 2, 1);
  expect_at(d.sub("sand").at("E").where(), "system/materials", 5, 5);
  expect_at(d.sub("sand").where(), "system/materials", 3, 1);
  expect_at(d.at("after").where(), "system/controlDict", 4, 1);
  expect_at(d.sub("block").at("deep").where(), "system/sub/nested.dict", 1, 1);
  expect_at(d.sub("block").at("more").where(), "system/more", 2, 1);
  EXPECT_EQ(d.sub("block").name(), "block");

  // Without a display name, the path as given is the file name.
  Dictionary plain = Dictionary::read_file(main);
  expect_at(plain.at("base").where(), main.string(), 1, 1);
  expect_at(plain.at("rho").where(), (main.parent_path() / "materials").string(), 2, 1);
}

TEST(DictionaryInclude, ParseResolvesIncludesRelativeToTheNamesDirectory) {
  TempDir dir;
  dir.write("inc", "x 5;");
  Dictionary d = Dictionary::parse("#include \"inc\"\ny $x;", (dir.path() / "virtual.dict").string());
  EXPECT_EQ(d.get_integer("y"), 5);
}

TEST(DictionaryInclude, Errors) {
  TempDir dir;
  const fs::path a = dir.write("a.dict()", "x 1;\n#include \"b.dict()\"\n");
  dir.write("b.dict()", "y 2;\n\n#include \"a.dict()\"\n");
  check_error(error_of([&] { Dictionary::read_file(a, "a.dict()"); }), "b.dict()", 3, 1,
              "include cycle: a.dict() includes b.dict() which includes a.dict()");

  const fs::path self = dir.write("self.dict", "// me again\n  #include \"self.dict\"\n");
  check_error(error_of([&] { Dictionary::read_file(self, "self.dict"); }), "self.dict", 2, 3,
              "include cycle: self.dict includes self.dict");

  const fs::path three = dir.write("c1", "#include \"c2\"");
  dir.write("c2", "#include \"c3\"");
  dir.write("c3", "a 1;\n#include \"c1\"");
  check_error(error_of([&] { Dictionary::read_file(three, "c1"); }), "c3", 2, 1,
              "include cycle: c1 includes c2 which includes c3 which includes c1");

  const fs::path missing = dir.write("missing.dict", "a 1;\n#include \"nowhere/x.dict()\"\n");
  const InputError e = error_of([&] { Dictionary::read_file(missing, "missing.dict"); });
  check_error(e, "missing.dict", 2, 1, "cannot open include file 'nowhere/x.dict()' (looked for ");
  EXPECT_NE(e.message().find((dir.path() / "nowhere/x.dict()").string()), std::string::npos) << e.message();

  const fs::path directory = dir.write("dir.dict", "#include \".\"\n");
  check_error(error_of([&] { Dictionary::read_file(directory, "dir.dict"); }), "dir.dict", 1, 1, "is a directory");

  // An error inside an included file is reported in that file.
  dir.write("broken", "good 1;\nbad 1.2.3;\n");
  const fs::path includer = dir.write("includer", "#include \"broken\"\n");
  check_error(error_of([&] { Dictionary::read_file(includer, "case/includer"); }), "case/broken", 2, 5,
              "bad number '1.2.3'");

  // Blocks cannot span files.
  dir.write("closer", "}\n");
  const fs::path opener = dir.write("opener", "a {\n#include \"closer\"\n");
  check_error(error_of([&] { Dictionary::read_file(opener, "opener"); }), "closer", 1, 1,
              "unexpected '}': no '{' is open in this included file");

  // A missing top-level file.
  const InputError top = error_of([&] { Dictionary::read_file(dir.path() / "absent", "system/absent"); });
  ASSERT_TRUE(top.where().file);
  EXPECT_EQ(*top.where().file, "system/absent");
  EXPECT_NE(top.message().find("cannot open file 'system/absent'"), std::string::npos) << top.message();
}

/// Runs `read`, which must throw an InputError without blocking on the named pipe `fifo`:
/// should it block in open() or read(), a watchdog writes to the pipe after 3 s, which
/// releases it, and the test fails (instead of hanging until CTest's timeout).
InputError error_without_blocking(const fs::path& fifo, const std::function<void()>& read) {
  std::atomic<bool> done{false}, released{false};
  std::thread watchdog([&] {
    for (int i = 0; i < 60 && !done; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (done) return;
    const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);  // succeeds only with a reader waiting
    if (fd >= 0) {
      released = true;
      const char text[] = "released 1;\n";
      [[maybe_unused]] const auto n = ::write(fd, text, sizeof text - 1);
      ::close(fd);
    }
  });
  InputError e = error_of(read);
  done = true;
  watchdog.join();
  EXPECT_FALSE(released) << "reading blocked on the named pipe " << fifo;
  return e;
}

// Reading a named pipe blocks until something writes to it: a FIFO in place of
// constant/g hung `scree --check` forever. Anything but a regular file is refused, naming
// the path, before it is opened.
TEST(DictionaryInclude, FilesThatAreNotRegularFilesAreRefusedWithoutBlocking) {
  TempDir dir;
  const fs::path fifo = dir.path() / "g";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const InputError top = error_without_blocking(fifo, [&] { Dictionary::read_file(fifo, "constant/g"); });
  ASSERT_TRUE(top.where().file);
  EXPECT_EQ(*top.where().file, "constant/g");
  EXPECT_NE(top.message().find(fifo.string() + " is a named pipe (FIFO), not a regular file"), std::string::npos)
      << top.message();
  const fs::path includer = dir.write("controlDict", "a 1;\n#include \"g\"\n");
  check_error(error_without_blocking(fifo, [&] { Dictionary::read_file(includer, "system/controlDict"); }),
              "system/controlDict", 2, 1, "cannot include 'g': " + fifo.string() + " is a named pipe (FIFO), not a regular file");
  const fs::path device = dir.write("dev", "#include \"/dev/null\"\n");
  check_error(error_of([&] { Dictionary::read_file(device, "dev"); }), "dev", 1, 1,
              "/dev/null is a character device, not a regular file");
  // A symbolic link to a regular file is read as that file.
  dir.write("real", "x 1;\n");
  fs::create_symlink(dir.path() / "real", dir.path() / "link");
  EXPECT_EQ(Dictionary::read_file(dir.path() / "link", "link").get_integer("x"), 1);
}

// An #include of a symbolic link that leads back to itself said "cannot open include
// file", as if the file were missing: it is an include loop, and the
// message names the links it goes round.
TEST(DictionaryInclude, SymbolicLinkLoopsAreReportedAsLoopsNamingTheChain) {
  TempDir dir;
  fs::create_directories(dir.path() / "constant");
  fs::create_symlink("loop2", dir.path() / "constant/loop");
  fs::create_symlink("loop", dir.path() / "constant/loop2");
  const fs::path includer = dir.write("constant/materialProperties", "a 1;\n#include \"loop\"\n");
  const InputError two = error_of([&] { Dictionary::read_file(includer, "constant/materialProperties"); });
  check_error(two, "constant/materialProperties", 2, 1,
              "include loop: symbolic links in a loop, which reaches no file: "
              "constant/loop -> constant/loop2 -> constant/loop");
  EXPECT_EQ(two.message().find("cannot open"), std::string::npos) << two.message();

  fs::create_symlink("self", dir.path() / "self");
  const fs::path self = dir.write("main", "#include \"self\"\n");
  check_error(error_of([&] { Dictionary::read_file(self, "main"); }), "main", 1, 1,
              "include loop: symbolic links in a loop, which reaches no file: self -> self");

  // A link to a directory that leads back to itself, in the path of the included file.
  fs::create_symlink("d2", dir.path() / "d1");
  fs::create_symlink("d1", dir.path() / "d2");
  const fs::path through = dir.write("through", "#include \"d1/x\"\n");
  check_error(error_of([&] { Dictionary::read_file(through, "through"); }), "through", 1, 1,
              "include loop: the directories of " + (dir.path() / "d1/x").string() +
                  " are symbolic links in a loop");

  // The file read first.
  const InputError top = error_of([&] { Dictionary::read_file(dir.path() / "constant/loop", "constant/loop"); });
  ASSERT_TRUE(top.where().file);
  EXPECT_EQ(*top.where().file, "constant/loop");
  EXPECT_NE(top.message().find("cannot read 'constant/loop': symbolic links in a loop, which reaches no file: "
                               "constant/loop -> constant/loop2 -> constant/loop"),
            std::string::npos)
      << top.message();
}

// An #include that cannot be opened is one error, at the directive's file:line, with
// nothing after it (the reader stops there).
TEST(DictionaryInclude, AnIncludeThatCannotBeOpenedIsReportedOnceWithItsLine) {
  TempDir dir;
  const fs::path includer =
      dir.write("case/constant/materialProperties", "a 1;\n#include \"../../columnCollapse/materials\"\nb $x;\n");
  const InputError e = error_of([&] { Dictionary::read_file(includer, "constant/materialProperties"); });
  check_error(e, "constant/materialProperties", 2, 1,
              "cannot open include file '../../columnCollapse/materials' (looked for " +
                  (dir.path() / "columnCollapse/materials").string() + ")");
  const std::string what = e.what();
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  EXPECT_EQ(what.find("cannot open"), what.rfind("cannot open")) << what;
}

TEST(DictionaryInclude, LongIncludeChainsAreLimited) {
  TempDir dir;
  for (int i = 0; i < 100; ++i)
    dir.write("f" + std::to_string(i), "v" + std::to_string(i) + " 1;\n#include \"f" + std::to_string(i + 1) + "\"\n");
  dir.write("f100", "end 1;\n");
  const InputError e = error_of([&] { Dictionary::read_file(dir.path() / "f0", "f0"); });
  EXPECT_NE(e.message().find("includes nested too deeply"), std::string::npos) << e.what();
  EXPECT_EQ(e.where().line, 2);
}

// ---------------------------------------------------------------------------------------
// Typed access and the Dictionary API
// ---------------------------------------------------------------------------------------

TEST(DictionaryAccess, TypedAccessorErrorsNameKeyExpectationAndFinding) {
  Dictionary d = parse(
      "endTime ten;\n"
      "n 2.5;\n"
      "big 99999999999999999999;\n"
      "whole 3.0;\n"
      "exp 1e3;\n"
      "flag maybe;\n"
      "g (0 x);\n"
      "w (a 2);\n"
      "two 1 2;\n"
      "s { a 1; }\n"
      "str \"text\";\n"
      "num 7;\n");
  auto msg = [&](const std::function<void()>& f) { return std::string(error_of(f).what()); };
  EXPECT_EQ(msg([&] { d.at("endTime").as_scalar(); }), "test.dict:1:1: endTime: expected a number, found the word 'ten'");
  EXPECT_EQ(msg([&] { d.at("n").as_integer(); }), "test.dict:2:1: n: expected an integer, found the number 2.5");
  EXPECT_EQ(msg([&] { d.at("big").as_integer(); }),
            "test.dict:3:1: big: expected an integer, found the number 99999999999999999999, which is out of range "
            "(the limit is +-9223372036854775807)");
  EXPECT_EQ(d.get_integer("whole"), 3);
  EXPECT_EQ(d.get_integer("exp"), 1000);
  EXPECT_EQ(msg([&] { d.at("flag").as_bool(); }),
            "test.dict:6:1: flag: expected a boolean (true/false, yes/no, on/off), found the word 'maybe'");
  EXPECT_EQ(msg([&] { d.at("g").as_scalar_list(); }),
            "test.dict:7:1: g: expected a list of numbers, but element 2 is the word 'x'");
  EXPECT_EQ(msg([&] { d.at("w").as_word_list(); }),
            "test.dict:8:1: w: expected a list of words, but element 2 is the number 2");
  EXPECT_EQ(msg([&] { d.at("two").as_scalar(); }), "test.dict:9:1: two: expected a number, found 2 values: 1 2");
  EXPECT_EQ(msg([&] { d.at("two").single_item(); }), "test.dict:9:1: two: expected a single value, found 2 values: 1 2");
  EXPECT_EQ(msg([&] { d.at("s").as_word(); }), "test.dict:10:1: s: expected a word, found a dictionary { a 1; }");
  EXPECT_EQ(msg([&] { d.at("str").as_scalar(); }), "test.dict:11:1: str: expected a number, found the string \"text\"");
  EXPECT_EQ(msg([&] { d.at("num").as_word(); }), "test.dict:12:1: num: expected a word, found the number 7");
  EXPECT_EQ(msg([&] { d.at("num").as_scalar_list(); }),
            "test.dict:12:1: num: expected a list of numbers, found the number 7");
  EXPECT_EQ(msg([&] { d.at("g").as_word(); }), "test.dict:7:1: g: expected a word, found the list (0 x)");
  EXPECT_EQ(msg([&] { d.at("num").dict(); }), "test.dict:12:1: 'num' must be a dictionary { ... }, found the number 7");
  EXPECT_EQ(msg([&] { d.sub("num"); }), "test.dict:12:1: 'num' must be a dictionary { ... }, found the number 7");
  EXPECT_EQ(msg([&] { d.at("nope"); }), "test.dict: missing required entry 'nope' in dictionary 'test.dict'");
  EXPECT_EQ(msg([&] { d.sub("s").at("b"); }), "test.dict:10:1: missing required entry 'b' in dictionary 's'");
  EXPECT_EQ(d.at("str").as_word(), "text");
  EXPECT_EQ(d.at("w").single_item().list()[0].text(), "a");

  // Integers beyond the range of long long written as floating point are rejected too.
  EXPECT_THROW(parse("x 1e19;").get_integer("x"), InputError);
  EXPECT_EQ(parse("x -9223372036854775808;").get_integer("x"), std::numeric_limits<long long>::min());
}

TEST(DictionaryAccess, DefaultsFindSetAndBuildingInCode) {
  Dictionary d = parse("a 1.5; b 4; c off; w word;");
  EXPECT_DOUBLE_EQ(d.get_scalar_or("a", 9), 1.5);
  EXPECT_DOUBLE_EQ(d.get_scalar_or("zz", 9), 9);
  EXPECT_EQ(d.get_integer_or("b", 0), 4);
  EXPECT_EQ(d.get_integer_or("zz", -1), -1);
  EXPECT_FALSE(d.get_bool_or("c", true));
  EXPECT_TRUE(d.get_bool_or("zz", true));
  EXPECT_EQ(d.get_word_or("w", "x"), "word");
  EXPECT_EQ(d.get_word_or("zz", "x"), "x");
  EXPECT_THROW(d.get_integer_or("a", 0), InputError);  // present but wrong: an error, not the default
  EXPECT_EQ(d.find("zz"), nullptr);
  ASSERT_NE(d.find("b"), nullptr);
  EXPECT_TRUE(d.has("w"));

  Dictionary built("built", {});
  Item n = Item::make_number(0.1, false);
  built.set(Entry("x", {}, std::vector<Item>{n}));
  Item w = Item::make_word("two words");  // not a word: written quoted
  built.set(Entry("y", {}, std::vector<Item>{w}));
  built.set(Entry("x", {}, std::vector<Item>{w}));
  EXPECT_EQ(built.keys(), (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(built.at("x").as_word(), "two words");
  EXPECT_EQ(built.at("y").value_string(), "\"two words\"");
  EXPECT_EQ(n.to_string(), "0.1");
  EXPECT_STREQ(error_of([&] { built.at("q"); }).what(), "missing required entry 'q' in dictionary 'built'");
  built.set_name("renamed");
  EXPECT_EQ(built.name(), "renamed");
}

TEST(DictionaryItems, TextsOfEveryLengthAreKeptAsWritten) {
  // Short texts are held in the item itself (numbers two characters a byte), longer ones
  // behind a pointer: every length reads back the same, copies and moves included.
  const std::string digits = "1234567890123456789012345";
  const std::string letters = "abcdefghijklmnopqrstuvwxy";
  for (std::size_t n = 1; n <= digits.size(); ++n) {
    SCOPED_TRACE(n);
    const std::string number = "-" + digits.substr(0, n) + "e-3";
    const std::string word = letters.substr(0, n);
    Dictionary d = parse("n " + number + "; w " + word + "; s \"" + word + " x\"; l (" + number + " " + word + ");");
    const Item& it = d.at("n").single_item();
    EXPECT_EQ(it.text(), number);
    EXPECT_EQ(it.to_string(), number);
    EXPECT_DOUBLE_EQ(it.number(), std::stod(number));
    EXPECT_FALSE(it.integral());
    EXPECT_EQ(d.at("w").single_item().text(), word);
    EXPECT_EQ(d.at("s").single_item().text(), word + " x");
    Item copy = d.at("l").single_item();
    Item moved = std::move(copy);
    EXPECT_EQ(moved.to_string(), "(" + number + " " + word + ")");
    copy = moved;
    EXPECT_EQ(copy.list()[1].text(), word);
    expect_at(copy.list()[1].where(), "test.dict", 1, static_cast<int>(21 + 2 * number.size() + 2 * word.size()));
  }
  EXPECT_EQ(sizeof(Item), 24u);
  EXPECT_EQ(Item::make_number(2.5, false).to_string(), "2.5");
  EXPECT_EQ(Item::make_number(1e6, true).to_string(), "1000000");
  EXPECT_TRUE(std::isnan(Item::make_number(std::nan(""), false).number()));
  EXPECT_EQ(Item::make_number(-INFINITY, false).number(), -INFINITY);
  EXPECT_THROW(Item::make_number("ten"), std::invalid_argument);
}

TEST(DictionaryItems, ManyKeysAreFoundAndReplacedInPlace) {
  // Past the entries held as a vector (4096) and across several of the blocks beyond.
  const int n = 40000;
  Dictionary d("many", {});
  for (int i = 0; i < n; ++i) d.set(Entry("k" + std::to_string(i), {}, {Item::make_number(i, true)}));
  for (int i = 0; i < n; i += 3) d.set(Entry("k" + std::to_string(i), {}, {Item::make_word("x")}));
  ASSERT_EQ(d.entries().size(), static_cast<std::size_t>(n));
  auto check = [&](const Dictionary& c) {
    int k = 0;
    for (const Entry& e : c.entries()) ASSERT_EQ(e.key(), "k" + std::to_string(k++));
    ASSERT_EQ(k, n);
    for (int i = 0; i < n; ++i) {
      ASSERT_NE(c.find("k" + std::to_string(i)), nullptr) << i;
      EXPECT_EQ(c.position("k" + std::to_string(i)), static_cast<std::size_t>(i));
      ASSERT_EQ(c.entries()[static_cast<std::size_t>(i)].key(), "k" + std::to_string(i));
      ASSERT_EQ(c.at("k" + std::to_string(i)).value_string(), i % 3 ? std::to_string(i) : "x");
    }
    EXPECT_EQ(c.find("k" + std::to_string(n)), nullptr);
    EXPECT_EQ(c.position("k" + std::to_string(n)), Dictionary::npos);
  };
  check(d);
  Dictionary copy = d;  // a deep copy, then a move, keep every entry in its place
  check(copy);
  Dictionary moved = std::move(copy);
  check(moved);
  copy = moved;
  check(copy);
}

TEST(DictionaryWrite, ToStringRoundTrips) {
  Dictionary d = parse(kControlDict, "system/controlDict");
  const std::string text = d.to_string();
  EXPECT_NE(text.find("FoamFile\n{\n    version         2.0;"), std::string::npos) << text;
  EXPECT_NE(text.find("gravity         (0 -9.81);\n"), std::string::npos) << text;
  EXPECT_NE(text.find("title           \"Column \\\"collapse\\\"\";\n"), std::string::npos) << text;
  EXPECT_NE(text.find("materials\n{\n    sand\n    {\n        type            mohrCoulomb;"), std::string::npos)
      << text;
  EXPECT_TRUE(round_trips(d));

  Dictionary tricky = parse(
      "\"a key\" \"x\\\\y\\\"z\";\n"
      "n (+3 2. .5 -0 1e-400 007);\n"
      "l ( ( ) { } { s { t (1 { u v; }); } } \"\" );\n"
      "e { }\n");
  EXPECT_TRUE(round_trips(tricky));
  EXPECT_EQ(tricky.at("l").value_string(), "(() { } { s { t (1 { u v; }); } } \"\")");
  EXPECT_EQ(tricky.at("e").value_string(), "{ }");
  // Indentation applies to every line.
  EXPECT_EQ(parse("a 1; b { c 2; }").to_string(2), "  a               1;\n  b\n  {\n      c               2;\n  }\n");
}

// ---------------------------------------------------------------------------------------
// Malformed input: every error located exactly
// ---------------------------------------------------------------------------------------

TEST(DictionaryErrors, UnterminatedBlock) {
  EXPECT_PARSE_ERROR("a 1;\nb\n{\n    c 2;\n", 5, 1, "unterminated block: '{' opened at line 3 has no matching '}'");
  EXPECT_PARSE_ERROR("x { y { z 1; }", 1, 15, "'{' opened at line 1 has no matching '}' (dictionary 'x')");
}

TEST(DictionaryErrors, MissingSemicolon) {
  // Between two entries: reported just after the value that lacks it.
  EXPECT_PARSE_ERROR("startTime 0;\nendTime 10\ndeltaT 0.1;\n", 2, 11,
                     "expected ';' after the value of 'endTime', found the word 'deltaT' on line 3");
  // At the end of the file.
  EXPECT_PARSE_ERROR("a 1;\nendTime 10", 2, 11, "expected ';' after the value of 'endTime', found the end of the file");
  // Before a closing brace, a sub-dictionary, a macro entry or a directive.
  EXPECT_PARSE_ERROR("s\n{\n    rho 2650\n}\n", 3, 13, "expected ';' after the value of 'rho', found '}' on line 4");
  EXPECT_PARSE_ERROR("a (1 2)\nb { }", 1, 8, "expected ';' after the value of 'a', found the word 'b' on line 2");
  EXPECT_PARSE_ERROR("x 1; a 1\n$x", 1, 9, "expected ';' after the value of 'a', found the macro '$x' on line 2");
  EXPECT_PARSE_ERROR("a \"s\"\n#include \"f\"", 1, 6,
                     "expected ';' after the value of 'a', found the directive '#include' on line 2");
  EXPECT_PARSE_ERROR("a 1 b { }", 1, 7, "unexpected '{' in the value of 'a'");
  // A value may continue on the next line when that line does not start with a word.
  EXPECT_EQ(parse("region box\n    (0 0)\n    (1 1);").at("region").items().size(), 3u);
  EXPECT_EQ(parse("type\n    linearElastic;").get_word("type"), "linearElastic");
}

TEST(DictionaryErrors, BadNumbers) {
  EXPECT_PARSE_ERROR("a 1;\nb 1.2.3;", 2, 3, "bad number '1.2.3'");
  EXPECT_PARSE_ERROR("b 1e;", 1, 3, "bad number '1e'");
  EXPECT_PARSE_ERROR("b    3x;", 1, 6, "bad number '3x'");
  EXPECT_PARSE_ERROR("b --1;", 1, 3, "bad number '--1'");
  EXPECT_PARSE_ERROR("b (1 .5. 2);", 1, 6, "bad number '.5.'");
  EXPECT_PARSE_ERROR("b 1e+;", 1, 3, "bad number '1e+'");
  EXPECT_PARSE_ERROR("b 0x1F;", 1, 3, "bad number '0x1F'");
  EXPECT_PARSE_ERROR("b 1e999;", 1, 3, "number '1e999' is out of range");
  EXPECT_PARSE_ERROR("b -2e400;", 1, 3, "number '-2e400' is out of range");
  check_error(parse_error("b 3x;"), "test.dict", 1, 3, "a word must start with a letter or '_'");
}

TEST(DictionaryErrors, UnknownMacros) {
  EXPECT_PARSE_ERROR("a 1;\nb $foo;", 2, 3, "unknown macro '$foo' (no entry 'foo' in scope)");
  EXPECT_PARSE_ERROR("a { b 1; }\nc $a.c;", 2, 3, "unknown macro '$a.c' (dictionary 'a' has no entry 'c')");
  EXPECT_PARSE_ERROR("a 1;\nc $a.b;", 2, 3, "unknown macro '$a.b' ('a' is not a dictionary)");
  EXPECT_PARSE_ERROR("s { a 1; b $:a; }", 1, 12, "unknown macro '$:a' (no entry 'a' at the top level)");
  EXPECT_PARSE_ERROR("a 1; b ${nope};", 1, 8, "unknown macro '$nope'");
  EXPECT_PARSE_ERROR("l (1 $x);", 1, 6, "unknown macro '$x'");
  EXPECT_PARSE_ERROR("s { $missing; }", 1, 5, "unknown macro '$missing'");
  EXPECT_PARSE_ERROR("a $b..c;", 1, 3, "malformed macro name '$b..c'");
  // Near misses are suggested.
  EXPECT_PARSE_ERROR("density 2650;\ns { rho $densty; }", 2, 9,
                     "unknown macro '$densty' (no entry 'densty' in scope; did you mean '$density'?)");
  EXPECT_PARSE_ERROR("m { sand { rho 1; } }\nx $m.snad.rho;", 2, 3,
                     "unknown macro '$m.snad.rho' (dictionary 'm' has no entry 'snad'; did you mean 'sand'?)");
}

TEST(DictionaryErrors, MacroMisuse) {
  EXPECT_PARSE_ERROR("a 1;\n$a;", 2, 1, "'$a' stands where an entry is expected, so it must name a dictionary");
  EXPECT_PARSE_ERROR("d { x 1; }\ne $d 2;", 2, 3, "'$d' is a dictionary");
  EXPECT_PARSE_ERROR("a $;", 1, 3, "expected a macro name after '$', found ';'");
  EXPECT_PARSE_ERROR("a ${b;", 1, 3, "unterminated '${'");
  EXPECT_PARSE_ERROR("a ${};", 1, 3, "empty macro name '${}'");
}

TEST(DictionaryErrors, Directives) {
  EXPECT_PARSE_ERROR("a 1;\n#include\nb 2;", 2, 1, "expected a quoted file name after '#include', found the word 'b'");
  EXPECT_PARSE_ERROR("#include", 1, 1, "expected a quoted file name after '#include', found the end of the file");
  EXPECT_PARSE_ERROR("#include \"\"", 1, 10, "empty file name after '#include'");
  EXPECT_PARSE_ERROR("a 1;\n  #includeEtc \"x\"", 2, 3, "cannot find '#includeEtc' file 'x'");
  EXPECT_PARSE_ERROR("#includeEtc", 1, 1, "expected a quoted file name after '#includeEtc', found the end of the file");
  EXPECT_PARSE_ERROR("a 1;\n  #includeFunc \"x\"", 2, 3,
                     "unknown directive '#includeFunc' (supported: #include \"file\"; #includeEtc \"file\"; "
                     "#inputMode overwrite|merge|error)");
  EXPECT_PARSE_ERROR("#remove a;", 1, 1, "unknown directive '#remove'");
  EXPECT_PARSE_ERROR("# include \"x\"", 1, 1, "expected a directive name after '#'");
  EXPECT_PARSE_ERROR("#inputMode protect", 1, 12, "expected 'overwrite', 'merge' or 'error' after '#inputMode'");
  EXPECT_PARSE_ERROR("l ( #include \"x\" );", 1, 5, "unexpected directive '#include' inside a list");
  EXPECT_PARSE_ERROR("a #include \"x\";", 1, 3, "unexpected directive '#include' in the value of 'a'");
}

TEST(DictionaryErrors, UnterminatedStringAndComment) {
  EXPECT_PARSE_ERROR("a 1;\nb \"open\nc 2;", 2, 3, "unterminated string: no closing '\"' before the end of the line");
  EXPECT_PARSE_ERROR("a \"open at the end", 1, 3, "unterminated string: no closing '\"' before the end of the file");
  EXPECT_PARSE_ERROR("a \"escaped quote\\\";", 1, 3, "unterminated string");
  EXPECT_PARSE_ERROR("a 1;\n/* never\nclosed", 2, 1, "unterminated comment: '/*' has no matching '*/'");
  EXPECT_PARSE_ERROR("a 1; /* /* */ */", 1, 15, "unexpected '*/' outside a comment (block comments do not nest)");
}

TEST(DictionaryErrors, StrayPunctuation) {
  EXPECT_PARSE_ERROR("a 1;\n)", 2, 1, "unmatched ')'");
  EXPECT_PARSE_ERROR("a 1 );", 1, 5, "unmatched ')' in the value of 'a'");
  EXPECT_PARSE_ERROR("a 1;\n}\n", 2, 1, "unexpected '}': no '{' is open");
  EXPECT_PARSE_ERROR("a 1;\n;", 2, 1, "unexpected ';' with no key or value before it");
  EXPECT_PARSE_ERROR("a 1;;", 1, 5, "unexpected ';'");
  EXPECT_PARSE_ERROR("a 1;\n{ b 1; }", 2, 1, "expected a key before '{'");
  EXPECT_PARSE_ERROR("(1 2);", 1, 1, "expected a key, found '('");
}

TEST(DictionaryErrors, MissingValue) {
  EXPECT_PARSE_ERROR("a 1;\nkey ;", 2, 5, "expected a value for 'key', found ';'");
  EXPECT_PARSE_ERROR("s { key }", 1, 9, "expected a value for 'key', found '}'");
  EXPECT_PARSE_ERROR("a 1;\nkey", 2, 4, "expected a value for 'key', found the end of the file");
}

TEST(DictionaryErrors, UnterminatedLists) {
  EXPECT_PARSE_ERROR("a 1;\nb (1 2\n", 3, 1, "unterminated list: '(' opened at line 2, column 3 has no matching ')'");
  EXPECT_PARSE_ERROR("b (1 2;\nc 3;", 1, 7, "expected ')' to close the list opened at line 1, column 3, found ';'");
  EXPECT_PARSE_ERROR("b ((1 2) (3 4);", 1, 15, "expected ')' to close the list opened at line 1, column 3, found ';'");
  EXPECT_PARSE_ERROR("b (1 (2 3);", 1, 11, "list opened at line 1, column 3");
  EXPECT_PARSE_ERROR("s { b (1 2 }", 1, 12, "expected ')' to close the list opened at line 1, column 7, found '}'");
  EXPECT_PARSE_ERROR("b ( { x 1; );", 1, 12, "unmatched ')'");  // the '{' is still open
}

TEST(DictionaryErrors, KeyThatIsANumber) {
  EXPECT_PARSE_ERROR("a 1;\n12 x;", 2, 1, "expected a key, found the number 12");
  EXPECT_PARSE_ERROR("s { -3.5 x; }", 1, 5, "expected a key, found the number -3.5");
  EXPECT_PARSE_ERROR("2D true;", 1, 1, "bad number '2D'");
}

TEST(DictionaryErrors, HeaderMustBeADictionary) {
  EXPECT_PARSE_ERROR("FoamFile 2;", 1, 1, "the FoamFile header must be a dictionary");
  EXPECT_EQ(parse("s { FoamFile 2; }").sub("s").get_integer("FoamFile"), 2);  // only at file level
}

TEST(DictionaryErrors, BinaryGarbage) {
  EXPECT_PARSE_ERROR(std::string("a 1;\nb 2\0;", 10), 2, 4, "unexpected NUL byte");
  EXPECT_PARSE_ERROR(std::string("// comment \0 hidden\n", 20), 1, 12, "unexpected NUL byte");
  EXPECT_PARSE_ERROR(std::string("\0\0\0\0", 4), 1, 1, "unexpected NUL byte");
  EXPECT_PARSE_ERROR("a 1;\n  b \x01;", 2, 5, "unexpected control character (byte 0x01");
  EXPECT_PARSE_ERROR("a \x7f;", 1, 3, "unexpected control character (byte 0x7f");
  // Bytes of invalid UTF-8 are just word bytes.
  EXPECT_EQ(parse("a \xff\xfe;").at("a").single_item().text(), "\xff\xfe");
}

TEST(DictionaryErrors, NestingBeyondTheLimit) {
  std::string dicts;
  for (int i = 0; i < 300; ++i) dicts += "a {\n";
  EXPECT_PARSE_ERROR(dicts, 257, 3, "nesting too deep: more than 256 levels");
  std::string lists = "a ";
  for (int i = 0; i < 100000; ++i) lists += '(';
  EXPECT_PARSE_ERROR(lists, 1, 259, "nesting too deep");
  std::string mixed = "a ";
  for (int i = 0; i < 200; ++i) mixed += "( { b ";
  EXPECT_PARSE_ERROR(mixed, 1, 3 + 6 * 128, "nesting too deep");
  // 256 levels are fine.
  std::string ok = "a ";
  for (int i = 0; i < 256; ++i) ok += '(';
  for (int i = 0; i < 256; ++i) ok += ')';
  EXPECT_NO_THROW(parse(ok + ";"));
  // Macros cannot build structure deeper than the limit either.
  std::string grow = "m0 (1);\n";
  for (int i = 1; i < 300; ++i) grow += "m" + std::to_string(i) + " ($m" + std::to_string(i - 1) + ");\n";
  const InputError e = parse_error(grow);
  EXPECT_NE(e.message().find("nesting too deep after expanding '$m"), std::string::npos) << e.what();
  EXPECT_EQ(e.where().line, 257);  // m256 would be 257 levels deep
}

TEST(DictionaryErrors, ExponentialMacrosAreStopped) {
  std::string text = "a0 (1 2 3 4 5 6 7 8 9 10);\n";
  for (int i = 1; i < 12; ++i) {
    const std::string prev = "$a" + std::to_string(i - 1);
    text += "a" + std::to_string(i) + " (" + prev + " " + prev + " " + prev + " " + prev + " " + prev + " " + prev +
            " " + prev + " " + prev + " " + prev + " " + prev + ");\n";
  }
  const auto start = std::chrono::steady_clock::now();
  const InputError e = parse_error(text);
  EXPECT_NE(e.message().find("macro expansion too large"), std::string::npos) << e.what();
  EXPECT_EQ(e.where().line, 6);  // a5 would copy more than a million values
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  // The same with dictionaries merged into dictionaries.
  std::string dicts = "d0 { a 1; b 2; c 3; d 4; }\n";
  for (int i = 1; i < 30; ++i) {
    const std::string prev = "$d" + std::to_string(i - 1);
    dicts += "d" + std::to_string(i) + " { x " + prev + "; y " + prev + "; z { " + prev + "; } }\n";
  }
  EXPECT_NE(parse_error(dicts).message().find("macro expansion too large"), std::string::npos);
}

TEST(DictionaryErrors, HugeFilesParseInLinearTime) {
  std::string text;
  const int n = 200000;
  text.reserve(static_cast<std::size_t>(n) * 16);
  for (int i = 0; i < n; ++i) text += "key" + std::to_string(i) + " " + std::to_string(i) + ";\n";
  const auto start = std::chrono::steady_clock::now();
  Dictionary d = parse(text);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  EXPECT_EQ(d.entries().size(), static_cast<std::size_t>(n));
  EXPECT_EQ(d.get_integer("key123456"), 123456);
  expect_at(d.at("key199999").where(), "test.dict", n, 1);
}

// ---------------------------------------------------------------------------------------
// Fuzz: random and mutated inputs either parse (and then round-trip) or throw InputError
// ---------------------------------------------------------------------------------------

std::string random_fragments(std::mt19937& rng) {
  static const std::vector<std::string> fragments = {
      "{", "}", "(", ")", ";", " ", "\n", "\r\n", "\t", "a", "b", "key", "sub", "1", "-2.5", "1e3", ".5", "2.",
      "1.2.3", "\"s\"", "\"", "\\", "$a", "$b.c", "$:a", "${a}", "$", "${", "#include \"x\"", "#include \"self\"",
      "#include", "#inputMode merge", "#bogus", "//c\n", "/*", "*/", "/* c */", "FoamFile", "true", "\xC3\xA9",
      "\x01", std::string(1, '\0'), "a 1;", "b { c 2; }", "l (1 (2 3) { d 4; });", "$a;", "m $b;", "e\n$a"};
  std::uniform_int_distribution<std::size_t> pick(0, fragments.size() - 1);
  std::uniform_int_distribution<int> count(0, 60);
  std::string s;
  for (int n = count(rng); n > 0; --n) s += fragments[pick(rng)];
  return s;
}

/// Mostly well-formed dictionaries: every construct, random layout and comments.
class Generator {
 public:
  explicit Generator(std::mt19937& rng) : rng_(rng) {}

  std::string dictionary() {
    values_.clear();
    dicts_.clear();
    std::string s;
    if (chance(10)) s += "FoamFile { version 2.0; object x; }\n";
    entries(s, 0);
    return s;
  }

 private:
  bool chance(int percent) { return static_cast<int>(rng_() % 100) < percent; }
  const std::string& pick(const std::vector<std::string>& v) { return v[rng_() % v.size()]; }

  void space(std::string& s) {
    static const std::vector<std::string> gaps = {" ", " ", " ", "\n", "\t", "\r\n", " /* c */ ", " // c\n", "\n\n"};
    s += pick(gaps);
  }

  /// A key not yet used in this dictionary, mostly: a key set twice in one file is an
  /// error, which one key in ten exercises.
  std::string key_for(std::vector<std::string>& used) {
    std::vector<std::string> unused;
    for (const auto& k : keys_)
      if (std::find(used.begin(), used.end(), k) == used.end()) unused.push_back(k);
    const std::string key = unused.empty() || chance(10) ? pick(keys_) : pick(unused);
    used.push_back(key);
    return key;
  }

  void entries(std::string& s, int depth) {
    std::vector<std::string> used;
    for (int n = static_cast<int>(rng_() % 6); n > 0; --n) {
      const int what = static_cast<int>(rng_() % 100);
      if (what < 60) {
        const std::string key = key_for(used);
        s += key;
        space(s);
        value(s, depth);
        s += ';';
        if (depth == 0) values_.push_back(key);
      } else if (what < 80 && depth < 4) {
        const std::string key = key_for(used);
        s += key;
        space(s);
        s += '{';
        space(s);
        entries(s, depth + 1);
        s += '}';
        if (depth == 0) dicts_.push_back(key);
      } else if (what < 86) {
        // Merge a dictionary defined before (rarely anything: often an error).
        s += chance(5) ? "$" + pick(keys_) + ";" : dicts_.empty() ? "/**/" : "$:" + pick(dicts_) + ";";
      } else if (what < 94) {
        if (chance(50)) {
          s += "#include \"x\"";
          if (depth == 0) values_.push_back("xa"), dicts_.push_back("xs");
        } else {
          s += "#inputMode merge";
        }
      } else {
        s += "// line comment\n";
      }
      space(s);
    }
  }

  void value(std::string& s, int depth) {
    for (int n = 1 + static_cast<int>(rng_() % 3); n > 0; --n) {
      item(s, depth);
      if (n > 1) s += ' ';
    }
  }

  void item(std::string& s, int depth) {
    static const std::vector<std::string> numbers = {"0", "1", "-9.81", "1e-5", "+3", ".5", "2.", "6.02e23", "-0", "007"};
    static const std::vector<std::string> words = {"yes", "off", "linear", "a.b:c", "x-y", "_w", "caf\xC3\xA9", "/p/q"};
    static const std::vector<std::string> strings = {"\"\"", "\"s p\"", "\"q\\\"x\"", "\"b\\\\s\"", "\"{;}\""};
    const int what = static_cast<int>(rng_() % 100);
    if (what < 30) s += pick(numbers);
    else if (what < 50) s += pick(words);
    else if (what < 60) s += pick(strings);
    else if (what < 66) s += chance(5) ? "$" + pick(keys_) : values_.empty() ? "w" : "$:" + pick(values_);
    else if (what < 90 && depth < 6) {
      s += '(';
      for (int n = static_cast<int>(rng_() % 5); n > 0; --n) {
        item(s, depth + 1);
        space(s);
      }
      s += ')';
    } else if (depth < 6) {
      s += "( {";
      space(s);
      entries(s, depth + 1);
      s += "} )";
    } else {
      s += "1";
    }
  }

  std::mt19937& rng_;
  std::vector<std::string> values_, dicts_;  // top-level keys defined so far
  const std::vector<std::string> keys_ = {"a", "b", "c", "rho", "sub", "x", "xa", "xs"};
};

std::string mutate(std::string s, std::mt19937& rng) {
  std::uniform_int_distribution<int> ops(1, 6);
  for (int n = ops(rng); n > 0; --n) {
    if (s.empty()) s = "a";
    std::uniform_int_distribution<std::size_t> pos(0, s.size() - 1);
    const std::size_t p = pos(rng);
    switch (rng() % 6) {
      case 0: s.erase(p, rng() % 8); break;                                      // delete a few bytes
      case 1: s[p] = static_cast<char>(rng() % 256); break;                      // replace a byte
      case 2: s.insert(p, 1, "{}();\"$#/*\\\n "[rng() % 14]); break;           // insert punctuation
      case 3: s.insert(p, s.substr(pos(rng), rng() % 16)); break;              // duplicate a piece
      case 4: s.resize(p); break;                                              // truncate
      case 5: s.insert(p, random_fragments(rng).substr(0, 12)); break;       // insert fragments
    }
  }
  return s;
}

/// An integer from the environment (for longer fuzz runs), or `fallback`.
long env_or(const char* name, long fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::strtol(v, nullptr, 10) : fallback;
}

// For a longer campaign: SCREE_FUZZ_ITERATIONS=1000000 SCREE_FUZZ_SEED=7 test_dictionary
TEST(DictionaryFuzz, RandomAndMutatedInputsParseOrThrowInputError) {
  const long iterations = env_or("SCREE_FUZZ_ITERATIONS", 5000);
  TempDir dir;
  dir.write("x", "xa 1; xs { y $xa; }\n");
  dir.write("self", "#include \"self\"\n");
  const std::string name = (dir.path() / "fuzz.dict").string();
  const std::vector<std::string> corpus = {
      kControlDict,
      "a 1;\nb { c $a; d (1 2 { e $c; }); }\nf $b;\ng { $b; h ${b.c}; }\n#include \"x\"\nz $xs.y;\n",
      "l ( (1 2) (3 (4 5)) \"s\\\"t\" w );\nm $l;\nn ($l $l);\n/* c */ o -1e-3; // end\n",
      "s { t { u { v $:s.w; } } w 1; }\r\nx \"y\";\r\n"};
  std::mt19937 rng(static_cast<std::uint32_t>(env_or("SCREE_FUZZ_SEED", 20240611)));
  int parsed = 0, rejected = 0;
  const auto start = std::chrono::steady_clock::now();
  Generator generate(rng);
  for (long i = 0; i < iterations; ++i) {
    std::string text;
    switch (i % 5) {
      case 0: text = random_fragments(rng); break;
      case 1: text = mutate(corpus[rng() % corpus.size()], rng); break;
      case 2: {
        std::uniform_int_distribution<int> len(0, 200);
        for (int n = len(rng); n > 0; --n) text += static_cast<char>(rng() % 256);
        break;
      }
      case 3: text = generate.dictionary(); break;
      case 4: text = mutate(generate.dictionary(), rng); break;
    }
    try {
      Dictionary d = Dictionary::parse(text, name);
      ++parsed;
      EXPECT_TRUE(round_trips(d)) << "input #" << i << ":\n" << text;
    } catch (const InputError& e) {
      ++rejected;
      ASSERT_TRUE(e.where().file) << "input #" << i;
      EXPECT_GE(e.where().line, 1) << e.what();
      EXPECT_GE(e.where().column, 1) << e.what();
      EXPECT_FALSE(e.message().empty());
    }
    // Anything else (another exception, a crash, a hang) fails the test.
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GT(parsed, iterations / 6);
  EXPECT_GT(rejected, iterations / 3);
  // Typically a fraction of a second for the default 5000 inputs.
  EXPECT_LT(seconds, 10.0 * std::max(1.0, static_cast<double>(iterations) / 5000.0));
  std::printf("fuzz: %d parsed, %d rejected in %.3f s\n", parsed, rejected, seconds);
}

}  // namespace

// OpenFOAM dimension sets: `[ ... ]` is a list like `( ... )` and closes with ']'.
TEST(DictionaryBrackets, DimensionSetIsAList) {
  const scree::Dictionary d = scree::Dictionary::parse(
      "dimensions [0 1 -2 0 0 0 0];\nvalue (0 -9.81 0);\nnested ([1 2] (3 4));\n", "constant/g");
  const auto dims = d.at("dimensions").as_scalar_list();
  ASSERT_EQ(dims.size(), 7u);
  EXPECT_EQ(dims[2], -2);
  EXPECT_EQ(d.at("nested").single_item().list().size(), 2u);
}

TEST(DictionaryBrackets, MismatchedBracketsAreErrors) {
  auto expect_error = [](const char* text, const char* where, const char* what) {
    try {
      scree::Dictionary::parse(text, "f");
      FAIL() << "no error for " << text;
    } catch (const scree::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_error("d [0 1 -2);", "f:1:10:", "expected ']'");
  expect_error("d (0 1 -2];", "f:1:10:", "expected ')'");
  expect_error("d [0 1 -2;", "f:1:10:", "expected ']'");
  expect_error("d 1 ];", "f:1:5:", "unmatched ']'");
  expect_error("] x;", "f:1:1:", "unmatched ']'");
}

// ---------------------------------------------------------------------------------------
// #includeEtc: the shipped parameter sets (etc/materials/feng2025), found from libscree.

namespace {
/// Feng et al. (2025) Table 3 and Table 1 in SI units. Decisions where the table misprints:
/// the particle density is in kg/m^3 (printed kg/m^2), p_at = 101.3 kPa; T0 need only be
/// negligibly small, so its value is not checked.
struct Column {
  const char* file;
  const char* type;
  std::vector<std::pair<const char*, double>> values;
};
std::vector<Column> paper_sets() {
  const std::vector<std::pair<const char*, double>> cc = {
      {"particleDensity", 2650}, {"referenceBulkModulus", 120}, {"poissonRatio", 0.2},
      {"atmosphericPressure", 101300}, {"elasticExponent", 0.5}, {"criticalFrictionAngle", 19.8},
      {"referenceCriticalVoidRatio", 0.977}, {"criticalStateLambda", 0.0596}, {"criticalStateXi", 0.365},
      {"dilatancyConstant", 0.7}, {"plasticModulusConstant", 0.0044}, {"peakStrengthExponent", 2.4},
      {"phaseTransformationExponent", 2.9}, {"initialVoidRatio", 0.95}};
  const std::vector<std::pair<const char*, double>> fl = {
      {"particleDensity", 2500}, {"referenceBulkModulus", 130}, {"poissonRatio", 0.2},
      {"atmosphericPressure", 101300}, {"elasticExponent", 0.5}, {"criticalFrictionAngle", 38},
      {"referenceCriticalVoidRatio", 0.977}, {"criticalStateLambda", 0.0596}, {"criticalStateXi", 0.365},
      {"dilatancyConstant", 0.4}, {"plasticModulusConstant", 0.0044}, {"peakStrengthExponent", 2.4},
      {"phaseTransformationExponent", 2.9}, {"initialVoidRatio", 0.90}};
  auto with = [](std::vector<std::pair<const char*, double>> v, std::vector<std::pair<const char*, double>> more) {
    v.insert(v.end(), more.begin(), more.end());
    return v;
  };
  return {
      {"table3-columnCollapse-frictional", "simsand", cc},
      {"table3-columnCollapse", "phaseTransition",
       with(cc, {{"diameter", 1.25e-3}, {"voidRatioSd", 0.62}, {"solidFractionM", 0.4},
                 {"restitutionCoefficient", 0.6}, {"particleFriction", 0.2}})},
      {"table3-flume-frictional", "simsand", fl},
      {"table3-flume", "phaseTransition",
       with(fl, {{"diameter", 1e-3}, {"voidRatioSd", 0.60}, {"solidFractionM", 0.4}, {"restitutionCoefficient", 0.6},
                 {"particleFriction", 0.2}})},
      {"table3-polystyreneBeads", "phaseTransition",
       {{"particleDensity", 1050}, {"diameter", 1e-3}, {"voidRatioSd", 0.92}, {"solidFractionM", 0.4},
        {"restitutionCoefficient", 0.7}, {"particleFriction", 0.1}, {"referenceBulkModulus", 120},
        {"poissonRatio", 0.235}, {"atmosphericPressure", 101300}, {"elasticExponent", 0.5},
        {"criticalFrictionAngle", 23}, {"referenceCriticalVoidRatio", 0.910}, {"criticalStateLambda", 0.122},
        {"criticalStateXi", 0.71}, {"dilatancyConstant", 0.5}, {"plasticModulusConstant", 0.001},
        {"peakStrengthExponent", 1}, {"phaseTransformationExponent", 1}}},
      {"table1-sand", "simsand",
       {{"referenceBulkModulus", 150}, {"poissonRatio", 0.22}, {"elasticExponent", 0.6},
        {"atmosphericPressure", 101300}, {"criticalFrictionAngle", 30}, {"referenceCriticalVoidRatio", 0.937},
        {"criticalStateLambda", 0.022}, {"criticalStateXi", 0.71}, {"dilatancyConstant", 4},
        {"plasticModulusConstant", 0.001}, {"peakStrengthExponent", 1}, {"phaseTransformationExponent", 1}}},
  };
}
}  // namespace

TEST(IncludeEtc, ShippedSetsHoldThePapersTables) {
  for (const Column& c : paper_sets()) {
    const Dictionary d =
        parse(std::string("m { #includeEtc \"materials/feng2025/") + c.file + "\" }", "materialProperties");
    const Dictionary& m = d.sub("m");
    EXPECT_EQ(m.get_word("type"), c.type) << c.file;
    for (const auto& [key, value] : c.values) {
      ASSERT_TRUE(m.has(key)) << c.file << ": " << key;
      EXPECT_EQ(m.get_scalar(key), value) << c.file << ": " << key;
    }
  }
}

TEST(IncludeEtc, AnEntryAfterTheIncludeReplacesIt) {
  const Dictionary d = parse(
      "m { #includeEtc \"materials/feng2025/table3-columnCollapse\"\n initialVoidRatio 0.90; }", "materialProperties");
  EXPECT_EQ(d.sub("m").get_scalar("initialVoidRatio"), 0.90);
  EXPECT_EQ(d.sub("m").get_scalar("criticalFrictionAngle"), 19.8);
  EXPECT_EQ(d.sub("m").at("initialVoidRatio").where().line, 2);
}

TEST(IncludeEtc, AMissingFileIsNamedWithWhereItWasLookedForAndWhatIsShipped) {
  try {
    parse("m {\n #includeEtc \"materials/feng2025/table9\"\n}", "materialProperties");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("materialProperties:2:", 0), 0u) << what;
    EXPECT_NE(what.find("cannot find '#includeEtc' file 'materials/feng2025/table9'"), std::string::npos) << what;
    EXPECT_NE(what.find("SCREE_ETC"), std::string::npos) << what;
    EXPECT_NE(what.find("materials/feng2025/table3-flume"), std::string::npos) << what;
  }
}

TEST(IncludeEtc, TheFoldersOfScreeEtcComeFirst) {
  TempDir dir;
  dir.write("materials/feng2025/table3-flume", "type mine; criticalFrictionAngle 30;\n");
  const char* before = std::getenv("SCREE_ETC");
  const std::string saved = before ? before : "";
  ::setenv("SCREE_ETC", ("/nonexistent:" + dir.path().string()).c_str(), 1);
  const Dictionary d = parse("m { #includeEtc \"materials/feng2025/table3-flume\" }");
  const Dictionary shipped = parse("m { #includeEtc \"materials/feng2025/table3-columnCollapse\" }");
  if (before)
    ::setenv("SCREE_ETC", saved.c_str(), 1);
  else
    ::unsetenv("SCREE_ETC");
  EXPECT_EQ(d.sub("m").get_word("type"), "mine");
  EXPECT_EQ(d.sub("m").get_scalar("criticalFrictionAngle"), 30);
  EXPECT_EQ(shipped.sub("m").get_word("type"), "phaseTransition") << "the shipped folder is still searched";
}
