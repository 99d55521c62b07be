#version 460
// The workgroups of a pass that runs one thread per counted item, as a
// VkDispatchIndirectCommand: the passes over stored photons (photon cells and order, splat,
// clearance), whose count is the photon counters' first word, and the list scatter, whose count
// is the splat counters' first word (the records). A frame's photon buffer has room for every
// path to store max_bounces photons, but most paths end sooner (about one photon a path in the
// atrium), so dispatching over the capacity ran seven workgroups of eight only to return.

layout(local_size_x = 1) in;

layout(push_constant) uniform PhotonDispatchParams {
    uint capacity;    // items the buffer holds: a count beyond it is clamped to it
    uint group_size;  // items per workgroup of the pass dispatched (a thread or a cluster each)
    uint max_groups;  // workgroups at most; a pass over more items loops (list_scatter.comp)
    uint pad1;
} params;
// The count is the first word of the counters.
layout(set = 1, binding = 0, std430) readonly buffer Counters { uint words[]; } counters;
layout(set = 1, binding = 1, std430) writeonly buffer PhotonDispatch { uint x; uint y; uint z; } photon_dispatch;

void main() {
    uint items = min(counters.words[0], params.capacity);
    photon_dispatch.x = min((items + params.group_size - 1u) / params.group_size, params.max_groups);
    photon_dispatch.y = 1u;
    photon_dispatch.z = 1u;
}
