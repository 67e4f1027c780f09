/// @file
/// The one way geovor writes a file (every feature writer, the index file, the tool's text
/// outputs): the output is written under a temporary name in the target's folder and renamed into
/// place only when complete, so that a target never holds half a file.
///
/// The rules, in one place:
/// - **Temporary names are short**: `.gv-PID-N.tmp` (at most 30 bytes) in the target's folder
///   (the same file system, so the final rename is atomic), whatever the length of the target's
///   name: a 255-byte output name can be written.
/// - **No clobbering**: without `overwrite`, the commit never replaces a file, not even one that
///   appeared while geovor was running (renameat2(RENAME_NOREPLACE), or link() then unlink()
///   where the file system refuses that flag); the existence check at the start only fails early.
/// - **Nothing left behind**: the temporary is removed on every error (the destructor), and on
///   SIGINT, SIGTERM and SIGHUP once install_output_cleanup() was called: every live temporary is
///   registered in a fixed, async-signal-safe table that the handler empties before the signal
///   ends the process as it would have (exit status 130, 143, 129 in a shell).
/// - **One file, one output**: check_distinct_outputs() refuses two outputs of one command that
///   are the same file (the same path, an alias such as `./X` or `a/../X`, a hard or symbolic
///   link, `-` twice) before any work.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace geovor {

/// What an output path names now (check_output_target).
enum class OutputTargetState {
  Absent,   ///< nothing there (or a dangling symbolic link, replaced by the commit)
  Regular,  ///< an existing regular file that may be replaced (overwrite)
  Special,  ///< a device or a FIFO (/dev/null, /dev/stdout): written in place, never renamed over
};

/// The one message for an output that exists and may not be replaced (the option `overwrite` of
/// every writer is off; --overwrite on every command): "PATH: exists; use --overwrite to replace
/// it", then `more` (a writer's other way out, e.g. ", or --update to add a layer to it").
std::string output_exists(const std::string& path, const std::string& more = {});

/// Refuses an output that exists before a long job (the writers check again, atomically, when
/// they commit): Error(Io) output_exists(path) when anything exists at `path` (a link followed; a
/// device too), unless `overwrite`, or `path` is "" (no output) or "-" (stdout).
void refuse_existing_output(const std::string& path, bool overwrite);

/// Checks an output path before any work. "-" (stdout) is Special.
/// @exception Error(Io) "PATH: is a directory"; "PATH: exists; use --overwrite to replace it"
///   if something exists there, is not a device or a FIFO, and `overwrite` is false.
OutputTargetState check_output_target(const std::string& path, bool overwrite);

/// A temporary file or directory next to an output, removed unless committed.
class TemporaryOutput {
 public:
  enum class Kind { File, Directory };

  TemporaryOutput() = default;
  /// Creates a new temporary in the folder of `target` (".", if it names none): a file (O_EXCL,
  /// mode 0666 less the umask, open for writing: take_fd()) or a directory (mode 0700, for writers
  /// that make several files, renamed one by one with rename_into_place). It is registered for
  /// removal on SIGINT/SIGTERM/SIGHUP (install_output_cleanup).
  /// @exception Error(Io) "TARGET: cannot create the temporary file TEMP: REASON" (or directory).
  TemporaryOutput(const std::string& target, Kind kind);
  /// discard(), unless committed.
  ~TemporaryOutput();
  TemporaryOutput(TemporaryOutput&& other) noexcept;
  TemporaryOutput& operator=(TemporaryOutput&& other) noexcept;
  TemporaryOutput(const TemporaryOutput&) = delete;
  TemporaryOutput& operator=(const TemporaryOutput&) = delete;

  /// The temporary's path ("" once committed or discarded).
  const std::string& path() const { return path_; }
  bool active() const { return !path_.empty(); }
  /// A file's descriptor, now owned by the caller (who closes it before commit()); -1 after the
  /// first call and for a directory.
  int take_fd();
  /// take_fd() as a stdio stream ("wb"), owned by the caller (who fcloses it before commit()).
  /// @exception Error(Io) naming `target` if the stream cannot be made; the temporary is then
  ///   removed.
  std::FILE* take_stdio(const std::string& target);

  /// Moves the temporary file to `target` (rename_into_place) and forgets it. On failure the
  /// temporary is removed and Error(Io) names the target: "TARGET: exists; use --overwrite to
  /// replace it" when a file appeared there meanwhile, else "TARGET: cannot rename TEMP to it: REASON".
  void commit(const std::string& target, bool overwrite);
  /// Forgets the temporary without removing it (a directory whose files were moved out by the
  /// caller, then removed by it).
  void release() noexcept;
  /// Removes the temporary (a directory with everything in it) and closes a descriptor not taken.
  void discard() noexcept;

 private:
  std::string path_;
  Kind kind_ = Kind::File;
  int fd_ = -1;
  int slot_ = -1;  // in the signal registry, or -1
};

/// Renames `from` to `to` (the same file system). With `overwrite`, rename(); without, never
/// replaces an existing `to`: renameat2(RENAME_NOREPLACE), or, where the file system refuses it,
/// link() then unlink() (both atomic refusals), or as a last resort (no hard links either) a
/// check then rename(). Returns 0, or the errno (EEXIST: `to` exists and was left alone).
int rename_into_place(const std::string& from, const std::string& to, bool overwrite) noexcept;

/// Whether two output paths name the same file: both "-"; the same device and inode where both
/// exist ("-" is stdout's; character devices such as /dev/null may be named twice, except as
/// "-" twice); else the same canonical folder and name (a file yet to be created).
bool same_output_file(const std::string& a, const std::string& b);

/// An output of a command, for check_distinct_outputs: the option that names it and its path
/// ("" when not given).
struct NamedOutput {
  std::string option;
  std::string path;
};
/// Refuses two outputs that are the same file (same_output_file), before any work.
/// @exception Error(InvalidArgument) "OPTION1 PATH1 and OPTION2 PATH2 are the same file; ...".
void check_distinct_outputs(const std::vector<NamedOutput>& outputs);

/// Installs handlers of SIGINT, SIGTERM and SIGHUP (those not ignored) that remove every
/// registered temporary, then end the process by the same signal (the shell's status 130, 143,
/// 129). Idempotent. The geovor tool calls it first thing; a library user may instead call
/// remove_registered_temporaries() from their own handler.
void install_output_cleanup();

/// The registry behind TemporaryOutput (64 entries; async-signal-safe to read).
/// register_temporary returns an entry (or -1 when full or the path is too long: the temporary is
/// then only removed on errors, not on signals); unregister_temporary(-1) does nothing.
int register_temporary(const char* path, bool directory) noexcept;
void unregister_temporary(int entry) noexcept;
/// Removes every registered temporary (async-signal-safe: unlink, rmdir, getdents64).
void remove_registered_temporaries() noexcept;

}  // namespace geovor
