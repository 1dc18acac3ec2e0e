#include "gapchain/report.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fcntl.h>
#include <fstream>
#include <numbers>
#include <sstream>
#include <sys/file.h>
#include <unistd.h>

namespace gapchain {

using nlohmann::json;

std::string to_json(const SimulationResult& r, const Scene& scene) {
    json j;
    j["F_m"] = r.F_m;
    j["F_m_error"] = r.F_m_error;
    j["F_m_error_method"] = to_string(r.error_method);
    j["F_m_contact"] = r.F_m_contact;
    j["F_m_time"] = r.F_m_time;
    j["contact"] = r.contact;
    if (scene.physical) {
        j["F_m_newton"] = force_in_newtons(r.F_m, *scene.physical);
        j["F_m_error_newton"] = force_in_newtons(r.F_m_error, *scene.physical);
        j["excitation"] = {{"harmonic", scene.harmonic()},
                           {"a0_m_s2", scene.physical->a0},
                           {"natural_frequency_hz", natural_frequency(*scene.physical)}};
        if (!scene.harmonic()) j["excitation"]["duration_s"] = scene.record_duration;
    }
    json bodies = json::array();
    for (const auto& b : r.per_body) {
        json e = {
            {"left", b.left}, {"right", b.right}, {"t_left", b.t_left}, {"t_right", b.t_right}};
        if (scene.physical) {
            e["left_newton"] = force_in_newtons(b.left, *scene.physical);
            e["right_newton"] = force_in_newtons(b.right, *scene.physical);
        }
        bodies.push_back(e);
    }
    j["per_body"] = bodies;
    json contacts = json::array();
    for (const auto& c : r.per_contact)
        contacts.push_back({{"force", c.force}, {"time", c.time}, {"impacts", c.impacts}});
    j["per_contact"] = contacts;
    j["steady_state_period"] = r.steady_state_period ? json(*r.steady_state_period) : json(nullptr);
    j["steady_state_time"] = r.steady_state_time ? json(*r.steady_state_time) : json(nullptr);
    j["status"] = std::string(to_string(r.status));
    j["scheme"] = std::string(to_string(r.scheme));
    j["step"] = r.step;
    j["periods_simulated"] = r.periods_simulated;
    j["steps"] = r.steps;
    j["evaluations"] = r.evaluations;
    j["wall_time_s"] = r.wall_time_s;
    const ReducedParameters& p = scene.reduced;
    j["parameters"] = {{"Nm", p.Nm},
                       {"fc", p.fc},
                       {"eps", p.eps},
                       {"e_r", p.e_r},
                       {"f_r", p.f_r},
                       {"periods", scene.run.periods},
                       {"transient_periods", scene.run.transient_periods},
                       {"tolerance", scene.run.tolerance}};
    j["scene"] = scene.source;
    return j.dump(2) + "\n";
}

OutputFile::OutputFile(std::string path) : m_path(std::move(path)) {
    m_temp = m_path + ".tmp." + std::to_string(::getpid());
    m_stream.open(m_temp, std::ios::out | std::ios::trunc);
    if (!m_stream) throw SceneError(m_path + ": cannot open for writing");
    m_stream.precision(17);
}

OutputFile::~OutputFile() {
    if (!m_committed) {
        m_stream.close();
        std::remove(m_temp.c_str());
    }
}

void OutputFile::commit() {
    m_stream.flush();
    const bool ok = static_cast<bool>(m_stream);
    m_stream.close();
    if (!ok || std::rename(m_temp.c_str(), m_path.c_str()) != 0) {
        std::remove(m_temp.c_str());
        m_committed = true;
        throw SceneError(m_path + ": cannot write the output file");
    }
    m_committed = true;
}

void write_file_atomically(const std::string& path, const std::string& text) {
    OutputFile f(path);
    f.stream() << text;
    f.commit();
}

std::string points_csv(const BifurcationResult& result, const SectionSpec& section,
                       SweptParameter parameter) {
    std::ostringstream os;
    os.precision(12);
    os << "value,direction,point,t";
    for (const auto& v : section.record)
        os << ',' << v.name();
    os << "\n# value is " << to_string(parameter) << "; point is " << section.record.front().name()
       << "\n";
    for (const auto& row : result.rows)
        for (const auto& p : row.points) {
            os << row.value << ',' << to_string(row.direction) << ',' << p.values.front() << ','
               << p.t;
            for (double v : p.values)
                os << ',' << v;
            os << '\n';
        }
    return os.str();
}

std::string summary_csv(const BifurcationResult& result, SweptParameter parameter) {
    std::ostringstream os;
    os.precision(12);
    os << "value,direction,F_m,period,points,status\n# value is " << to_string(parameter)
       << "; period 0 = not periodic\n";
    for (const auto& row : result.rows)
        os << row.value << ',' << to_string(row.direction) << ',' << row.F_m << ',' << row.period
           << ',' << row.points.size() << ',' << to_string(row.status) << '\n';
    return os.str();
}

std::string to_json(const ModalResult& r, int Nm, double fc) {
    json j;
    j["Nm"] = Nm;
    j["fc"] = fc;
    j["mode_numbers"] = r.mode_numbers;
    j["frequencies"] = r.frequencies;
    j["approx"] = r.approx;
    j["rel_error"] = r.rel_error;
    j["residuals"] = r.residuals;
    if (!r.shapes.empty()) j["shapes"] = r.shapes;
    j["method"] = std::string(to_string(r.method));
    j["status"] = r.status == ModalStatus::converged       ? "converged"
                  : r.status == ModalStatus::not_converged ? "not_converged"
                                                           : "numerical_issue";
    j["iterations"] = r.iterations;
    j["wall_time_s"] = r.wall_time_s;
    return j.dump(2) + "\n";
}

std::string grid_csv(const ApproximationGrid& grid) {
    std::ostringstream os;
    os.precision(10);
    os << "Nm,fc,f1_error,other_error,other_mode\n";
    for (const auto& p : grid.points)
        os << p.Nm << ',' << p.fc << ',' << p.first << ',' << p.other << ',' << p.other_mode
           << '\n';
    return os.str();
}

std::string to_json(const LyapunovResult& r, const ReducedParameters& p, int count) {
    json j;
    j["exponents"] = r.exponents;
    j["error"] = r.errors;
    j["sum"] = r.sum;
    if (count == 2 * p.Nm) j["expected_sum"] = -4.0 * std::numbers::pi * p.eps * p.Nm;
    j["averaging_time"] = r.averaging_time;
    j["units"] = "1 / reduced time";
    j["status"] = std::string(to_string(r.status));
    j["wall_time_s"] = r.wall_time_s;
    j["parameters"] = {{"Nm", p.Nm}, {"fc", p.fc}, {"eps", p.eps}, {"e_r", p.e_r}, {"f_r", p.f_r}};
    return j.dump(2) + "\n";
}

std::string history_csv(const LyapunovResult& r) {
    std::ostringstream os;
    os.precision(10);
    os << "t";
    for (std::size_t k = 0; k < r.exponents.size(); ++k)
        os << ",lambda" << k + 1;
    os << '\n';
    for (const auto& h : r.history) {
        os << h.t;
        for (double x : h.exponents)
            os << ',' << x;
        os << '\n';
    }
    return os.str();
}

namespace {
json classification_json(const Classification& c) {
    json j;
    j["regime"] = std::string(to_string(c.regime));
    j["period"] = c.period;
    j["lambda_max"] = c.lambda_max;
    j["lambda_max_error"] =
        std::isfinite(c.lambda_max_error) ? json(c.lambda_max_error) : json(nullptr);
    j["F_m"] = c.F_m;
    j["distinct_points"] = c.distinct_points;
    j["section_points"] = c.section_points;
    j["broadband_share"] = c.broadband_share;
    j["stopped_at_steady_state"] = c.stopped_at_steady_state;
    j["periods_run"] = c.periods_run;
    j["status"] = std::string(to_string(c.status));
    j["wall_time_s"] = c.wall_time_s;
    return j;
}
} // namespace

std::string to_json(const Classification& c, const ReducedParameters& p) {
    json j = classification_json(c);
    j["parameters"] = {{"Nm", p.Nm}, {"fc", p.fc}, {"eps", p.eps}, {"e_r", p.e_r}, {"f_r", p.f_r}};
    return j.dump(2) + "\n";
}

std::string map_csv(const RegimeMap& map) {
    std::ostringstream os;
    os.precision(10);
    os << "e_r,f_r,regime,code,period,F_m,lambda_max,lambda_max_error,distinct_points,broadband_"
          "share\n";
    for (std::size_t i = 0; i < map.e_r.size(); ++i)
        for (std::size_t k = 0; k < map.f_r.size(); ++k) {
            const Classification& c = map.cells[i * map.f_r.size() + k];
            os << map.e_r[i] << ',' << map.f_r[k] << ',' << to_string(c.regime) << ','
               << static_cast<int>(c.regime) << ',' << c.period << ',' << c.F_m << ','
               << c.lambda_max << ',' << c.lambda_max_error << ',' << c.distinct_points << ','
               << c.broadband_share << '\n';
        }
    return os.str();
}

std::string psd_csv(const Psd& psd, double f_r) {
    std::ostringstream os;
    os.precision(10);
    os << "f,f_over_f_r,density\n";
    for (std::size_t k = 0; k < psd.frequency.size(); ++k)
        os << psd.frequency[k] << ',' << psd.frequency[k] / f_r << ',' << psd.density[k] << '\n';
    return os.str();
}

std::string work_precision_csv(const WorkPrecision& study) {
    std::ostringstream os;
    os.precision(10);
    os << "scheme,tolerance,step,F_m,F_m_error,final_error,l2_error,seconds,evaluations\n";
    for (const auto& p : study.points)
        os << to_string(p.scheme) << (p.split ? "" : "-nosplit") << ',' << p.tolerance << ','
           << p.step << ',' << p.F_m << ',' << p.F_m_error << ',' << p.final_error << ','
           << p.l2_error << ',' << p.wall_time_s << ',' << p.evaluations << '\n';
    return os.str();
}

std::string sweep_csv_header(const Study& study) {
    std::string h = "index";
    for (const auto& a : study.axes)
        h += ",axis:" + a.key;
    h += ",Nm,fc,eps,e_r,f_r,F_m,F_m_error,status";
    if (parse_scene(study.scene_json).physical) h += ",F_m_newton";
    if (study.keep.steady_state) h += ",steady_state_period";
    if (study.keep.wall_time) h += ",wall_time_s";
    if (study.keep.regime) h += ",regime,period,lambda_max,lambda_max_error";
    if (study.keep.per_body) h += ",per_body";
    return h;
}

std::string sweep_csv_row(const Study& study, const SweepPointResult& r) {
    std::ostringstream os;
    os.precision(12);
    os << r.index;
    for (double v : r.values)
        os << ',' << v;
    const ReducedParameters& p = r.parameters;
    const SimulationResult& s = r.simulation;
    os << ',' << p.Nm << ',' << p.fc << ',' << p.eps << ',' << p.e_r << ',' << p.f_r << ',' << s.F_m
       << ',' << s.F_m_error << ',' << to_string(s.status);
    if (r.F_m_newton) os << ',' << *r.F_m_newton;
    if (study.keep.steady_state)
        os << ','
           << (s.steady_state_period ? std::to_string(*s.steady_state_period) : std::string(""));
    if (study.keep.wall_time) os << ',' << s.wall_time_s;
    if (study.keep.regime && r.regime)
        os << ',' << to_string(r.regime->regime) << ',' << r.regime->period << ','
           << r.regime->lambda_max << ',' << r.regime->lambda_max_error;
    if (study.keep.per_body) {
        os << ',';
        for (std::size_t i = 0; i < s.per_body.size(); ++i)
            os << (i ? ";" : "") << s.per_body[i].left << '|' << s.per_body[i].right;
    }
    return os.str();
}

std::string study_json(const Study& study) {
    nlohmann::ordered_json j;
    j["study"] = study.source;
    j["scene"] = nlohmann::ordered_json::parse(study.scene_json);
    for (const auto& a : study.axes)
        j["parameters"][a.key] = a.values;
    j["sample"] = study.sampling == Sampling::grid     ? "grid"
                  : study.sampling == Sampling::random ? "random"
                                                       : "latin_hypercube";
    j["samples"] = study.samples;
    j["seed"] = study.seed;
    j["points"] = point_count(study);
    j["columns"] = sweep_csv_header(study);
    j["build"] = {{"gapchain", GAPCHAIN_LIBRARY_VERSION},
                  {"compiler", __VERSION__},
                  {"built", __DATE__ " " __TIME__}};
    return j.dump(2) + "\n";
}

ResultLog::ResultLog(const std::string& path, const std::string& header, long index_count)
    : m_path(path), m_done(static_cast<std::size_t>(index_count), 0) {
    std::string existing;
    {
        std::ifstream in(path, std::ios::binary);
        if (in) {
            std::ostringstream text;
            text << in.rdbuf();
            existing = text.str();
        }
    }
    std::size_t keep = 0; // bytes of whole lines to keep
    if (!existing.empty()) {
        const std::size_t first = existing.find('\n');
        if (first == std::string::npos || existing.compare(0, first, header) != 0)
            throw SceneError(path + ": exists with other columns (another study?); remove it or "
                                    "choose another --out");
        keep = first + 1;
        std::size_t pos = keep;
        while (pos < existing.size()) {
            const std::size_t end = existing.find('\n', pos);
            if (end == std::string::npos) break; // torn last line: dropped
            const std::string line = existing.substr(pos, end - pos);
            char* tail = nullptr;
            const long index = std::strtol(line.c_str(), &tail, 10);
            if (tail == line.c_str() || *tail != ',' || index < 0 || index >= index_count)
                throw SceneError(path + ": unreadable row \"" + line.substr(0, 60) + "\"");
            m_done[index] = 1;
            ++m_rows_found;
            keep = end + 1;
            pos = end + 1;
        }
    }
    m_fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (m_fd < 0) throw SceneError(path + ": cannot open for writing");
    // One writer at a time: a second sweep on the same file (or a leftover process of a killed
    // one) would append points twice. The kernel drops the lock when its holder dies.
    if (::flock(m_fd, LOCK_EX | LOCK_NB) != 0)
        throw SceneError(path + ": is being written by another gapchain-sweep still running; "
                                "wait for it or stop it first");
    if (existing.empty()) {
        append(header);
    } else if (keep < existing.size() && ::ftruncate(m_fd, static_cast<off_t>(keep)) != 0) {
        throw SceneError(path + ": cannot drop the torn last row");
    }
}

ResultLog::~ResultLog() {
    if (m_fd >= 0) ::close(m_fd);
}

void ResultLog::append(const std::string& line) {
    const std::string whole = line + "\n";
    const ssize_t written = ::write(m_fd, whole.data(), whole.size());
    if (written != static_cast<ssize_t>(whole.size()))
        throw SceneError(m_path + ": cannot append a result row");
}

} // namespace gapchain
