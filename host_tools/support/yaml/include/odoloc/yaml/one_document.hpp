// A YAML file that holds one document: yaml-cpp's YAML::Load reads the
// first and silently ignores the rest (after a "---" or a "..."), so a
// layout, a sweep spec or a register map with a second document would
// lose it without a word.
#pragma once

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/parser.h>
#include <yaml-cpp/yaml.h>

#include <sstream>
#include <string>

namespace odoloc::yaml {

// The one document of `text`. Throws YAML::ParserException at the second
// document's start (its mark: line and column) when there is one, or
// yaml-cpp's own exceptions for text that is not YAML; the callers already
// report YAML::Exception with the file and the line.
inline YAML::Node load_one_document(const std::string& text) {
  // Only the documents' starts matter; the other events are ignored.
  struct DocumentStarts final : YAML::EventHandler {
    bool seen = false;
    void OnDocumentStart(const YAML::Mark& mark) override {
      if (seen)
        throw YAML::ParserException(mark, "a second document ('---' or '...')");
      seen = true;
    }
    void OnDocumentEnd() override {}
    void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
    void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
    void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  const std::string&) override {}
    void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                         YAML::EmitterStyle::value) override {}
    void OnSequenceEnd() override {}
    void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                    YAML::EmitterStyle::value) override {}
    void OnMapEnd() override {}
  };
  YAML::Node node = YAML::Load(text);  // its errors first: they point at the first document
  std::istringstream stream(text);
  YAML::Parser parser(stream);
  DocumentStarts starts;
  while (parser.HandleNextDocument(starts)) {
  }
  return node;
}

}  // namespace odoloc::yaml
