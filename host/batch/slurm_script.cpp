#include "batch/slurm_script.h"

#include <cctype>
#include <sstream>

#include "core/error.h"

namespace pcl {

namespace {

bool isAbsolute(const std::string& path) { return !path.empty() && path[0] == '/'; }

// A log path on an #SBATCH line: sbatch reads a double-quoted word there (spaces allowed) and
// expands %-patterns in --output, so a literal % in the folder is written %%; `pattern` (the file
// name) keeps its own, e.g. %a for the array index.
std::string sbatchLogPath(const std::string& folder, const std::string& pattern) {
    std::string out = "\"";
    for (char c : folder) out += c == '%' ? std::string("%%") : std::string(1, c);
    return out + "/" + pattern + "\"";
}

void requireAbsolute(const std::string& what, const std::string& path) {
    if (!isAbsolute(path))
        throw InputError("batch slurm: " + what + ": expected an absolute path, got \"" + path + "\"");
    // A newline would end the #SBATCH line or the command; sbatch cannot escape a double quote.
    if (path.find_first_of("\n\r\"") != std::string::npos)
        throw InputError("batch slurm: " + what + ": expected a path without newlines or double quotes, got \"" + path +
                         "\"");
}

// Values that go bare on an #SBATCH line: no blanks, quotes or newlines.
void requireWord(const std::string& what, const std::string& value) {
    for (char c : value)
        if (std::isspace(static_cast<unsigned char>(c)) || c == '"' || c == '\'' || c == '#')
            throw InputError("batch slurm: " + what + ": expected one word without blanks or quotes, got \"" + value +
                             "\"");
}

std::string dir(const SlurmSubmission& s) {
    return s.logDir.size() > 1 && s.logDir.back() == '/' ? s.logDir.substr(0, s.logDir.size() - 1) : s.logDir;
}

// The #SBATCH lines both jobs share: partition and time limit.
void commonDirectives(std::ostringstream& out, const SlurmSubmission& s) {
    if (!s.partition.empty()) out << "#SBATCH --partition=" << s.partition << "\n";
    if (!s.timeLimit.empty()) out << "#SBATCH --time=" << s.timeLimit << "\n";
}

}  // namespace

void checkSlurmSubmission(const SlurmSubmission& s) {
    if (s.shards == 0) throw InputError("batch slurm: shards: expected at least 1, got 0");
    requireAbsolute("photoncl binary", s.photoncl);
    requireAbsolute("job file", s.jobFile);
    requireAbsolute("--log-dir", s.logDir);
    if (s.jobName.empty()) throw InputError("batch slurm: --job-name: expected a name, got an empty one");
    requireWord("--job-name", s.jobName);
    requireWord("--partition", s.partition);
    requireWord("--time", s.timeLimit);  // --device goes shell-quoted on the command line: any name
}

std::string slurmShardScriptPath(const SlurmSubmission& s) { return dir(s) + "/shards.sbatch"; }
std::string slurmMergeScriptPath(const SlurmSubmission& s) { return dir(s) + "/merge.sbatch"; }

std::string slurmShardScript(const SlurmSubmission& s) {
    checkSlurmSubmission(s);
    std::ostringstream out;
    out << "#!/bin/bash\n"
        << "# photoncl batch slurm: " << s.shards << " shard" << (s.shards == 1 ? "" : "s") << " of " << s.jobFile
        << ", one per array task.\n"
        << "#SBATCH --job-name=" << s.jobName << "\n"
        << "#SBATCH --array=0-" << (s.shards - 1);
    if (s.maxRunning > 0) out << "%" << s.maxRunning;
    out << "\n"
        << "#SBATCH --output=" << sbatchLogPath(dir(s), "shard-%a.log") << "\n";
    commonDirectives(out, s);
    if (s.memPerTaskMib > 0) out << "#SBATCH --mem=" << s.memPerTaskMib << "M\n";
    if (s.cpusPerTask > 0) out << "#SBATCH --cpus-per-task=" << s.cpusPerTask << "\n";
    out << "set -eu\n"
        << "exec " << shellQuote(s.photoncl) << " batch run " << shellQuote(s.jobFile)
        << " --shard \"${SLURM_ARRAY_TASK_ID}/" << s.shards << "\"";
    if (!s.device.empty()) out << " --device " << shellQuote(s.device);
    out << "\n";
    return out.str();
}

std::string slurmMergeScript(const SlurmSubmission& s) {
    checkSlurmSubmission(s);
    std::ostringstream out;
    out << "#!/bin/bash\n"
        << "# photoncl batch slurm: merges the " << s.shards << " shard" << (s.shards == 1 ? "" : "s") << " of "
        << s.jobFile << " once every array task succeeded.\n"
        << "#SBATCH --job-name=" << s.jobName << "-merge\n"
        << "#SBATCH --output=" << sbatchLogPath(dir(s), "merge.log") << "\n";
    commonDirectives(out, s);
    out << "set -eu\n"
        << "exec " << shellQuote(s.photoncl) << " batch merge " << shellQuote(s.jobFile) << "\n";
    return out.str();
}

std::vector<std::string> sbatchShardCommand(const SlurmSubmission& s, const std::vector<std::string>& extraArgs) {
    std::vector<std::string> argv = {"sbatch", "--parsable"};
    argv.insert(argv.end(), extraArgs.begin(), extraArgs.end());
    argv.push_back(slurmShardScriptPath(s));
    return argv;
}

std::vector<std::string> sbatchMergeCommand(const SlurmSubmission& s, const std::string& shardJobId,
                                            const std::vector<std::string>& extraArgs) {
    // afterok on an array job waits for every task; a failed task makes the dependency
    // impossible, and --kill-on-invalid-dep cancels the merge instead of leaving it pending.
    std::vector<std::string> argv = {"sbatch", "--parsable", "--dependency=afterok:" + shardJobId,
                                     "--kill-on-invalid-dep=yes"};
    argv.insert(argv.end(), extraArgs.begin(), extraArgs.end());
    argv.push_back(slurmMergeScriptPath(s));
    return argv;
}

std::string parseSbatchJobId(const std::string& parsableOutput) {
    // --parsable prints "<id>" or "<id>;<cluster>"; warnings may come on lines before it.
    std::istringstream lines(parsableOutput);
    std::string line, id;
    while (std::getline(lines, line)) {
        std::string first = line.substr(0, line.find(';'));
        while (!first.empty() && std::isspace(static_cast<unsigned char>(first.back()))) first.pop_back();
        bool digits = !first.empty();
        for (char c : first) digits = digits && std::isdigit(static_cast<unsigned char>(c));
        if (digits) id = first;
    }
    if (id.empty())
        throw InputError("batch slurm: sbatch --parsable: expected a job id, got \"" + parsableOutput + "\"");
    return id;
}

std::string shellQuote(const std::string& word) {
    bool safe = !word.empty();
    for (char c : word)
        safe = safe &&
               (std::isalnum(static_cast<unsigned char>(c)) || std::string("/._-+=:,@%").find(c) != std::string::npos);
    if (safe) return word;
    std::string out = "'";
    for (char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::string shellCommandLine(const std::vector<std::string>& argv) {
    std::string line;
    for (const std::string& word : argv) line += (line.empty() ? "" : " ") + shellQuote(word);
    return line;
}

}  // namespace pcl
