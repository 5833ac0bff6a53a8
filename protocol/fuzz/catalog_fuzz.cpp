// Fuzzes the signal-catalog reader (the VSS JSON file behind --catalog, and the catalog a view
// receives over the link) as the processes use it: parse, then look every entry up by id and by
// name, build a signal table on it, and parse the catalog's own text again, which must give the
// same catalog (the hash a view checks after a transfer). A crash, a sanitizer report, an
// exception other than the parser's error result, or a broken invariant is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "meter/protocol/catalog.hpp"
#include "meter/protocol/signal_table.hpp"

using namespace meter::protocol;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const CatalogParseResult r = parse_catalog(text, "fuzz.vss.json");
  if (!r.catalog) {
    if (r.error.empty()) std::abort();  // a refusal always says why
    return 0;
  }
  if (!r.error.empty()) std::abort();
  const Catalog& c = *r.catalog;
  for (const SignalInfo& s : c.signals()) {
    if (c.find(s.id) != &s || c.find(s.name) != &s || !c.index_of(s.id)) std::abort();
    if (!(s.min <= s.max)) std::abort();  // a range the view can draw, never NaN
  }
  const SignalTable table(r.catalog);
  for (const SignalInfo& s : c.signals())
    if (!table.index_of(s.id)) std::abort();
  const CatalogParseResult again = parse_catalog(c.text(), "again.vss.json");
  if (!again.catalog || again.catalog->hash() != c.hash() || again.catalog->size() != c.size()) std::abort();
  return 0;
}
