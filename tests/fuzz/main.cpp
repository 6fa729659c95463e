/// atelier_fuzz: a structured mutation fuzzer over the bundled scenes, projects and fabric
/// presets and the small inputs of tests/fuzz/corpus. Each case is a seed input with a few
/// mutations (json_mutator.h, text_mutator.h), run in a forked child (sandbox.h) by the public
/// loaders and, when it loads, stepped a little (case_runner.h). Loaded-and-ran and refused
/// with a message both pass; a signal, a sanitizer report, an exception, a hang, a runaway
/// allocation or an empty message fail, and the input goes to the findings folder.
/// docs/testing.md says how to run it and how a finding becomes a regression case.

#include "sim/core/parallel.h"

#include "case_runner.h"
#include "fuzz_case.h"
#include "json_mutator.h"
#include "rng.h"
#include "sandbox.h"
#include "text_mutator.h"

#include <CLI/CLI.hpp>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <random>

#if ATELIER_FUZZ_ASAN
/// A runaway allocation is a report (the parent's memory limit catches many small ones).
extern "C" const char* __asan_default_options() {
    return "max_allocation_size_mb=2048:allocator_may_return_null=0";
}
#endif

namespace atelier::fuzz {

namespace fs = std::filesystem;

namespace {

struct Options {
    std::uint64_t seed = 0;
    long cases = 0;        ///< 0 = until the time budget
    double timeBudget = 0; ///< [s]; 0 = until `cases`
    long onlyCase = -1;    ///< run only this case of the seed
    std::vector<std::string> corpus;
    std::vector<std::string> replay;
    std::string findings = ATELIER_FUZZ_FINDINGS;
    int maxFindings = 10;
    bool verbose = false;
    SandboxLimits sandbox;
    RunLimits run;
};

/// Case `index` of the run with `seed`: a seed input with one to six mutations. Each file's
/// structural mutations are made in one pass (its raw text, such as 100 000 levels of nesting,
/// is spliced in at the end), the byte-level ones after them.
FuzzCase makeCase(const std::vector<FuzzCase>& corpus, const JsonMutator& mutator,
                  std::uint64_t seed, std::uint64_t index, std::vector<std::string>& notes) {
    Rng rng(seed, index);
    // One case in five starts from an input with files beside it (OBJ meshes, a materials
    // file): few seeds have them, and their paths and meshes are where readers block or grow.
    std::vector<FuzzCase> withFiles;
    if (rng.chance(20)) {
        std::copy_if(corpus.begin(), corpus.end(), std::back_inserter(withFiles),
                     [](const FuzzCase& s) { return s.files.size() > 1; });
    }
    FuzzCase c = rng.pick(withFiles.empty() ? corpus : withFiles);
    int count = 1;
    while (count < 6 && rng.chance(40)) {
        ++count;
    }
    std::vector<std::string> names;
    for (const auto& [name, text] : c.files) {
        names.push_back(name);
    }
    std::map<std::string, int> structural;
    std::vector<std::string> bytes;
    for (int k = 0; k < count; ++k) {
        const std::string name = rng.chance(70) ? c.mainName() : rng.pick(names);
        if (rng.chance(15)) {
            bytes.push_back(name);
        } else {
            ++structural[name];
        }
    }
    for (const auto& [name, mutations] : structural) {
        std::string& text = c.files[name];
        if (fs::path(name).extension() == ".obj") {
            for (int k = 0; k < mutations; ++k) {
                text = mutateObj(text, rng, notes);
            }
        } else if (fs::path(name).extension() == ".dxf") {
            for (int k = 0; k < mutations; ++k) {
                text = mutateDxf(text, rng, notes);
            }
        } else if (auto mutated = mutator.mutate(text, rng, mutations, notes)) {
            text = std::move(*mutated);
        } else {
            bytes.insert(bytes.end(), static_cast<std::size_t>(mutations), name);
        }
    }
    for (const std::string& name : bytes) {
        c.files[name] = mutateBytes(std::move(c.files[name]), rng, notes);
        notes.back() = name + ": " + notes.back();
    }
    return c;
}

/// Saves a failing case as `findings/seed-S-case-N` (+ its suffix, or a folder when it has
/// side files) with a `.log` beside it; returns the path to replay.
fs::path saveFinding(const FuzzCase& c, const CaseResult& result, const std::string& name,
                     const std::vector<std::string>& notes, const fs::path& findings) {
    fs::create_directories(findings);
    fs::path path;
    if (c.files.size() == 1) {
        path = findings / (name + std::string(kindSuffix(c.kind)));
        std::ofstream(path, std::ios::binary) << c.main();
    } else {
        path = findings / name;
        fs::remove_all(path);
        writeCase(c, path);
    }
    std::ofstream log(findings / (name + ".log"), std::ios::binary);
    log << "seed input: " << c.origin << "\nsymptom: " << result.summary() << "\nmutations:\n";
    for (const std::string& note : notes) {
        log << "  " << note << "\n";
    }
    log << "child output:\n" << result.log << "\n";
    return path;
}

void report(const std::string& what, const CaseResult& result,
            const std::vector<std::string>& notes) {
    std::cout << what << ": " << result.summary() << "\n";
    for (const std::string& note : notes) {
        std::cout << "    " << note << "\n";
    }
    if (!result.ok() && !result.log.empty()) {
        std::cout << "  child output:\n" << result.log << "\n";
    }
}

fs::path workDir() {
    return fs::temp_directory_path() / ("atelier-fuzz-" + std::to_string(::getpid()));
}

/// The mannequin of each base at its default measurements, built once (the children inherit
/// them).
BodyCache defaultBodies() {
    BodyCache bodies;
    for (const char* base : {"female", "male"}) {
        patterns::BodySource source;
        source.base = base;
        bodies.add(source);
    }
    return bodies;
}

int replay(const Options& o) {
    std::vector<FuzzCase> cases;
    for (const std::string& root : o.replay) {
        for (FuzzCase& c : readCases(root)) {
            cases.push_back(std::move(c));
        }
    }
    const BodyCache bodies = defaultBodies();
    int failures = 0;
    for (const FuzzCase& c : cases) {
        const CaseResult result = runForked(c, workDir(), bodies, o.run, o.sandbox);
        if (!result.ok()) {
            ++failures;
            report("FAILED " + c.origin, result, {});
        } else if (o.verbose) {
            report("ok " + c.origin, result, {});
        }
    }
    std::cout << "replayed " << cases.size() << " cases: " << failures << " failed\n";
    return cases.empty() || failures > 0 ? 1 : 0;
}

int fuzz(const Options& o) {
    std::vector<FuzzCase> corpus;
    std::vector<std::string> texts;
    for (const std::string& root : o.corpus) {
        for (FuzzCase& c : readCases(root)) {
            for (const auto& [name, text] : c.files) {
                texts.push_back(text);
            }
            corpus.push_back(std::move(c));
        }
    }
    if (corpus.empty()) {
        std::cerr << "atelier_fuzz: no seed inputs found\n";
        return 2;
    }
    const JsonMutator mutator(texts);
    const BodyCache bodies = defaultBodies();
    std::cout << "atelier_fuzz: seed " << o.seed << ", " << corpus.size() << " seed inputs"
              << (ATELIER_FUZZ_ASAN ? ", ASan" : "") << std::endl;
    std::map<std::string, long> outcomes;
    int failures = 0;
    const auto start = std::chrono::steady_clock::now();
    long index = o.onlyCase >= 0 ? o.onlyCase : 0;
    for (;; ++index) {
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const long done = index - std::max(o.onlyCase, 0L);
        if ((o.onlyCase >= 0 && done == 1) || (o.cases > 0 && done >= o.cases) ||
            (o.timeBudget > 0 && elapsed >= o.timeBudget) || failures >= o.maxFindings) {
            break;
        }
        std::vector<std::string> notes;
        const FuzzCase c =
            makeCase(corpus, mutator, o.seed, static_cast<std::uint64_t>(index), notes);
        const CaseResult result = runForked(c, workDir(), bodies, o.run, o.sandbox);
        const std::string name =
            "seed-" + std::to_string(o.seed) + "-case-" + std::to_string(index);
        const std::string summary = result.summary();
        ++outcomes[result.ok() ? summary.substr(0, summary.find(':')) : "FAILED"];
        if (!result.ok()) {
            ++failures;
            const fs::path path = saveFinding(c, result, name, notes, o.findings);
            report("FAILED " + name + " (" + c.origin + ")", result, notes);
            std::cout << "  input: " << path.string() << "\n  reproduce: atelier_fuzz --replay "
                      << path.string() << "\n  or: atelier_fuzz --seed " << o.seed
                      << " --only-case " << index << std::endl;
        } else if (o.verbose) {
            report(name + " (" + c.origin + ")", result, notes);
        }
    }
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "atelier_fuzz: seed " << o.seed << ", " << index - std::max(o.onlyCase, 0L)
              << " cases in " << static_cast<int>(elapsed) << " s:";
    for (const auto& [what, count] : outcomes) {
        std::cout << " " << what << " " << count << ";";
    }
    std::cout << " findings in " << o.findings << std::endl;
    return failures > 0 ? 1 : 0;
}

} // namespace

} // namespace atelier::fuzz

int main(int argc, char** argv) {
    using namespace atelier::fuzz;
    Options o;
    CLI::App app{"atelier_fuzz: mutation fuzzer of Atelier's file loaders"};
    app.add_option("--seed", o.seed, "seed of the mutations (default: from the clock, printed)");
    app.add_option("--cases", o.cases, "number of cases (0 = until the time budget)");
    app.add_option("--time-budget", o.timeBudget, "start no case after this many seconds");
    app.add_option("--only-case", o.onlyCase, "run case N of the seed alone (reproduction)");
    app.add_option("--corpus", o.corpus,
                   "seed inputs: files or folders (default: assets/ and "
                   "tests/fuzz/corpus/)");
    app.add_option("--replay", o.replay, "run these cases (files or folders) unmutated");
    app.add_option("--findings", o.findings, "where failing inputs are written");
    app.add_option("--max-findings", o.maxFindings, "stop after this many failures");
    app.add_option("--case-timeout", o.sandbox.seconds, "a case running longer hangs [s]");
    app.add_option("--memory-mb", o.sandbox.memoryMb, "a case using more memory fails [MiB]");
    app.add_flag("-v,--verbose", o.verbose, "print every case");
    CLI11_PARSE(app, argc, argv);
    if (app.count("--seed") == 0) {
        o.seed = std::random_device{}();
    }
    if (o.corpus.empty()) {
        o.corpus = {ATELIER_SOURCE_DIR "/assets", ATELIER_SOURCE_DIR "/tests/fuzz/corpus"};
    }
    if (o.cases == 0 && o.timeBudget <= 0) {
        o.timeBudget = 60;
    }
    if (!ATELIER_FUZZ_ASAN) {
        // The fuzzer itself stays bounded too (a mutation that grows without end throws).
        const rlim_t bytes = static_cast<rlim_t>(4 * o.sandbox.memoryMb) << 20;
        const rlimit limit{bytes, bytes};
        ::setrlimit(RLIMIT_AS, &limit);
    }
    // One thread: a forked child has only the thread that forked, and cases stay comparable.
    atelier::sim::setThreadCount(1);
    return o.replay.empty() ? fuzz(o) : replay(o);
}
