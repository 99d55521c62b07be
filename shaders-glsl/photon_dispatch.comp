#version 460
// The workgroups of the passes that run one thread per stored photon (photon cells and order,
// splat, clearance), as a VkDispatchIndirectCommand. A frame's buffer has room for every path
// to store max_bounces photons, but most paths end sooner (about one photon a path in the
// atrium), so dispatching over the capacity ran seven workgroups of eight only to return.

layout(local_size_x = 1) in;

layout(push_constant) uniform PhotonDispatchParams {
    uint capacity;    // photons the buffer holds: the count never exceeds it
    uint group_size;  // threads per workgroup of every per-photon pass
    uint pad0;
    uint pad1;
} params;
layout(set = 0, binding = 0, std430) readonly buffer PhotonCounters { uint stored; uint overflowed; uint rays; uint next_path; } photon_counters;
layout(set = 0, binding = 1, std430) writeonly buffer PhotonDispatch { uint x; uint y; uint z; } photon_dispatch;

void main() {
    uint photons = min(photon_counters.stored, params.capacity);
    photon_dispatch.x = (photons + params.group_size - 1u) / params.group_size;
    photon_dispatch.y = 1u;
    photon_dispatch.z = 1u;
}
