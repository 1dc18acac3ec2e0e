#pragma once
/// \file output_file.hpp
/// Output files that appear whole or not at all, and files rewritten in place that a failed or
/// abandoned run puts back as they were.

#include <fstream>
#include <stdexcept>
#include <string>

namespace gapchain {

/// An output that could not be written once the run was under way (disk full, I/O error): the
/// message names the file and the operating system's reason. Not bad input (tools exit 1).
class OutputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Undoes what this process's unfinished outputs did to the file system, from a signal handler
/// that then ends the process: removes the temporary of every open OutputFile, and puts back
/// every file a SetAsideFile not yet kept had set aside (removing the new file at its path).
/// Async-signal-safe (unlink(2) and rename(2) only).
void abandon_unfinished_outputs() noexcept;

/// Writes a file so that readers never see it half-written and a failure leaves nothing:
/// the text goes to a temporary file next to path, which is renamed over path on commit().
/// Destroying an uncommitted OutputFile removes the temporary.
class OutputFile {
public:
    /// Opens path + ".tmp.<pid>" for writing; throws SceneError naming the path and the
    /// system's reason if it cannot.
    explicit OutputFile(std::string path);
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;
    /// The stream to write to.
    std::ostream& stream() { return m_stream; }
    /// Flushes, closes and renames onto the final path; throws OutputError (file and reason) on
    /// I/O failure, leaving neither the temporary nor a partial file.
    void commit();

private:
    std::string m_path;
    std::string m_temp;
    std::ofstream m_stream;
    bool m_committed = false;
    int m_slot = -1; ///< registry slot of m_temp (abandon_unfinished_outputs)
};

/// Writes text to path through an OutputFile.
void write_file_atomically(const std::string& path, const std::string& text);

/// A file about to be rewritten in place before a run is over (a figure's data, which the
/// plotting program reads): whatever is at the path is renamed to path + ".gapchain-old.<pid>"
/// and, unless keep() is called, put back on destruction or by abandon_unfinished_outputs(),
/// the new file at the path removed. A path with nothing at it is left with nothing.
class SetAsideFile {
public:
    /// Sets aside the file at path, if any; throws OutputError naming it if it cannot.
    explicit SetAsideFile(std::string path);
    ~SetAsideFile();
    SetAsideFile(SetAsideFile&& other) noexcept;
    SetAsideFile& operator=(SetAsideFile&&) = delete;
    SetAsideFile(const SetAsideFile&) = delete;
    SetAsideFile& operator=(const SetAsideFile&) = delete;
    /// The new file stays: the previous one is removed.
    void keep();

private:
    std::string m_path;
    std::string m_aside; ///< where the previous file is; empty: there was none
    bool m_done = false; ///< kept, put back, or moved from
    int m_slot = -1;     ///< registry slot (abandon_unfinished_outputs)
};

} // namespace gapchain
