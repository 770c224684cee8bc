// study_results.h: the accuracy study's results on disk. One CSV schema (docs/accuracy/
// results.csv: one row per configuration, the numbers behind every figure of docs/accuracy.md),
// written and read here only; and the archive of a whole run (`simulate --study --save FILE`,
// `--load FILE`) that redoes the document and plots without simulating; the partial results of
// one shard of a study (`--shard K/N --save FILE`, merged by `--merge`).
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "study.h"

namespace retroprism::sim {

// Writes one row per configuration of `results` to `path`; InputError when it cannot.
void write_results_csv(const std::string& path, const std::vector<ConfigResult>& results);

// The configurations of a results.csv: every field of the schema filled in (the cross-sections
// and the fits' other members, which the CSV does not hold, stay empty). InputError naming the
// file and line for a missing column, a wrong field count or a field that is not a number.
std::vector<ConfigResult> read_results_csv(const std::string& path);
// The same from a stream; `path` names it in the errors.
std::vector<ConfigResult> parse_results_csv(std::istream& in, const std::string& path);

// The archive: the machine and date lines, then every number of the run, one per line.
void save_study(const std::string& path, const StudyResults& s);
// An archive written by save_study; InputError when it is truncated or its grid is not that of
// `quick` (the same --quick as the run that saved it).
StudyResults load_study(const std::string& path, bool quick);
// The same from a stream; `path` names it in the errors.
StudyResults parse_study(std::istream& in, const std::string& path, bool quick);

// The partial results of one shard (`simulate --study --shard K/N --save FILE`): a header line,
// the machine and date lines, then, as the archive writes them, the options, K, N, the grid, the
// shard's metadata, and each of its units' index, rays, seconds and results.
void save_study_shard(const std::string& path, const StudyShard& s);
// A shard written by save_study_shard, with source = path. InputError naming the file when it is
// not a shard's file, is truncated or too long, has K/N out of range, a grid other than this
// program's, or units out of order or not of its study.
StudyShard load_study_shard(const std::string& path);
// The same from a stream; `path` names it in the errors.
StudyShard parse_study_shard(std::istream& in, const std::string& path);

} // namespace retroprism::sim
