// Files for the dictionary reader (private): reading a case file or an included one
// whole, without ever blocking on something that is not a regular file, and the names
// and identities that messages and include-cycle detection use.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace scree::reader {

/// link_loop: symbolic links that lead back to themselves, never to a file (the system
/// says "too many levels of symbolic links"; a missing file is another thing to fix).
enum class ReadStatus { ok, missing, link_loop, directory, not_regular, unreadable };

/// Read a whole regular file. Anything else (a named pipe, a device, a socket) is refused
/// before it is opened: reading a FIFO blocks until a writer appears, a device may never
/// end. The file is then opened without blocking and checked again, so that a path
/// replaced in between cannot block either. `kind` receives the type of a refused path.
ReadStatus read_text(const std::filesystem::path& path, std::string& out, std::filesystem::file_type& kind);

/// What a path that is neither a regular file nor a directory is ("a named pipe").
std::string special_file_kind(std::filesystem::file_type t);

/// The symbolic links `shown` leads through, written "a -> b -> a" (each as the path a
/// user would type, from `shown`'s directory), up to where it comes back; "" when `path`
/// is not itself a link (the loop is then in a directory of the path).
std::string link_chain(const std::filesystem::path& path, const std::string& shown);

/// `p` made absolute and normal, for messages.
std::string absolute_text(const std::filesystem::path& p);

/// The folder of libscree itself: an installed tree, and the build tree that mirrors its
/// layout, find the plugins (<lib>/scree/plugins) and the shipped dictionaries from it.
std::filesystem::path library_dir();

/// Where `#includeEtc "file"` looks, in order: the folders of SCREE_ETC (separated by
/// ':'), then the shipped dictionaries (<prefix>/share/scree/etc, found from library_dir()).
std::vector<std::filesystem::path> etc_search_path();

/// A file being read: for include cycles, relative includes and display names.
struct OpenFile {
  std::filesystem::path path;  ///< as opened
  std::string display;         ///< name in messages
  std::optional<std::filesystem::path> canonical = {};  ///< computed when an #include needs it

  /// The file's canonical path (symbolic links resolved): two names of one file are equal.
  const std::filesystem::path& identity();
};

}  // namespace scree::reader
