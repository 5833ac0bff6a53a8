// The checks of one package record right after the reader decoded it (record_decoder.hpp): sizes
// that must agree, values in their ranges, integrity regions inside their frame. Records without
// any have none. Each names the record's path through `in.fail`.
#pragma once

#include "meter/engine/scene.hpp"

namespace meter::engine {

class RecordDecoder;

void check_record(const RecordDecoder& in, const VertexAttribute& a);
void check_record(const RecordDecoder& in, const Primitive& p);
void check_record(const RecordDecoder& in, const Texture& t);
void check_record(const RecordDecoder& in, const Skin& k);
void check_record(const RecordDecoder& in, const AnimSampler& s);
void check_record(const RecordDecoder& in, const AttributeInfo& a);
void check_record(const RecordDecoder& in, const UniformInfo& u);
void check_record(const RecordDecoder& in, const SamplerInfo& s);
void check_record(const RecordDecoder& in, const Environment& e);
void check_record(const RecordDecoder& in, const SafetyRegion& g);
void check_record(const RecordDecoder& in, const NeedleModel& n);
void check_record(const RecordDecoder& in, const IntegrityTable& t);
// Any other record: nothing to check.
template <class T>
void check_record(const RecordDecoder&, const T&) {}

}  // namespace meter::engine
