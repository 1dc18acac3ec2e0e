#include "gapchain/output_file.hpp"

#include "gapchain/scene.hpp"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sys/statvfs.h>
#include <unistd.h>

namespace gapchain {

namespace fs = std::filesystem;

namespace {

// What abandon_unfinished_outputs() does for one registered output.
enum class Undo {
    remove_temporary, // an OutputFile's temporary: unlink it
    put_back,         // a SetAsideFile: the previous file renamed back, or the new one removed
};

// The unfinished outputs, in fixed slots that a signal handler reads without allocating or
// locking. A slot is claimed, filled, then published: a handler never reads one being filled.
class UnfinishedOutputs {
public:
    // A slot for the output, or -1 if every slot is taken or a path is too long (the output is
    // then not undone by a signal, as before this registry).
    int publish(Undo undo, const std::string& path, const std::string& aside) {
        if (path.size() >= k_length || aside.size() >= k_length) return -1;
        for (int i = 0; i < k_slots; ++i) {
            bool expected = false;
            if (!m_slots[i].claimed.compare_exchange_strong(expected, true)) continue;
            Slot& s = m_slots[i];
            s.undo = undo;
            std::memcpy(s.path, path.c_str(), path.size() + 1);
            std::memcpy(s.aside, aside.c_str(), aside.size() + 1);
            s.used.store(true);
            return i;
        }
        return -1;
    }

    void release(int slot) noexcept {
        if (slot < 0) return;
        m_slots[slot].used.store(false);
        m_slots[slot].claimed.store(false);
    }

    // rename(2) replaces the new file by the previous one in one step; where there was none, the
    // new file goes, so that the path is as the run found it.
    void abandon() noexcept {
        for (Slot& s : m_slots) {
            if (!s.used.load()) continue;
            if (s.undo == Undo::put_back && s.aside[0] != '\0')
                ::rename(s.aside, s.path);
            else
                ::unlink(s.path);
        }
    }

private:
    static constexpr int k_slots = 64;
    static constexpr std::size_t k_length = 4096;
    struct Slot {
        char path[k_length];
        char aside[k_length];
        Undo undo;
        std::atomic<bool> claimed;
        std::atomic<bool> used;
    };
    Slot m_slots[k_slots];
};

UnfinishedOutputs g_unfinished;

/// Why writing path failed, given the errno saved at the failure (0 if none was): a stream that
/// failed in an earlier write keeps no errno, and a full disk was reported as "Success".
std::string write_failure_reason(const std::string& path, int saved) {
    if (saved != 0) return std::strerror(saved);
    struct statvfs fs {};
    if (::statvfs(path.c_str(), &fs) == 0 && fs.f_bavail == 0) return std::strerror(ENOSPC);
    return "a write failed (the file system gave no reason)";
}

} // namespace

void abandon_unfinished_outputs() noexcept {
    g_unfinished.abandon();
}

OutputFile::OutputFile(std::string path) : m_path(std::move(path)) {
    m_temp = m_path + ".tmp." + std::to_string(::getpid());
    m_slot = g_unfinished.publish(Undo::remove_temporary, m_temp, "");
    errno = 0;
    m_stream.open(m_temp, std::ios::out | std::ios::trunc);
    if (!m_stream) {
        const int saved = errno;
        g_unfinished.release(m_slot);
        throw SceneError(m_path +
                         ": cannot open for writing: " + write_failure_reason(m_path, saved));
    }
    m_stream.precision(17);
}

OutputFile::~OutputFile() {
    if (!m_committed) {
        m_stream.close();
        std::remove(m_temp.c_str());
    }
    g_unfinished.release(m_slot);
}

void OutputFile::commit() {
    errno = 0;
    m_stream.flush();
    const bool ok = static_cast<bool>(m_stream);
    const int flush_errno = errno;
    errno = 0;
    m_stream.close();
    const bool closed = static_cast<bool>(m_stream) || ok;
    int failure_errno = flush_errno ? flush_errno : errno;
    bool renamed = false;
    if (ok && closed) {
        errno = 0;
        renamed = std::rename(m_temp.c_str(), m_path.c_str()) == 0;
        if (!renamed) failure_errno = errno;
    }
    if (!renamed) {
        // The errno of the step that failed (a directory in the way of the rename said "a write
        // failed"); none when an earlier buffered write failed.
        const std::string why = write_failure_reason(m_temp, failure_errno);
        std::remove(m_temp.c_str());
        m_committed = true;
        throw OutputError(m_path + ": cannot write the output file: " + why);
    }
    m_committed = true;
}

void write_file_atomically(const std::string& path, const std::string& text) {
    OutputFile f(path);
    f.stream() << text;
    f.commit();
}

SetAsideFile::SetAsideFile(std::string path) : m_path(std::move(path)) {
    std::error_code ec;
    // symlink_status: a dangling link is set aside too, not replaced and lost.
    if (fs::exists(fs::symlink_status(m_path, ec))) {
        m_aside = m_path + ".gapchain-old." + std::to_string(::getpid());
        fs::rename(m_path, m_aside, ec);
        if (ec) throw OutputError(m_path + ": cannot set the previous file aside: " + ec.message());
    }
    // Published only once the file is aside: a handler running before would remove the
    // previous file itself as the new one.
    m_slot = g_unfinished.publish(Undo::put_back, m_path, m_aside);
}

SetAsideFile::SetAsideFile(SetAsideFile&& other) noexcept
    : m_path(std::move(other.m_path)), m_aside(std::move(other.m_aside)), m_done(other.m_done),
      m_slot(other.m_slot) {
    other.m_done = true;
    other.m_slot = -1;
}

SetAsideFile::~SetAsideFile() {
    if (m_done) return;
    std::error_code ec;
    fs::remove(m_path, ec);
    if (!m_aside.empty()) fs::rename(m_aside, m_path, ec);
    g_unfinished.release(m_slot);
}

void SetAsideFile::keep() {
    if (m_done) return;
    // Released first: a handler running between the two steps then leaves the previous file
    // aside, rather than removing the new one for a previous one already gone.
    g_unfinished.release(m_slot);
    m_slot = -1;
    std::error_code ec;
    if (!m_aside.empty()) fs::remove(m_aside, ec);
    m_done = true;
}

} // namespace gapchain
