"""The voxelized garment in the scene: a Volume object whose file is the
.vdb, at the garment's place and scale (the grid's own transform, the object
at the identity), and a material that renders it in Cycles as
docs/rendering.md says."""

import bpy


def extinction(yarn_radius, optical_depth):
    """Cycles' Density: the extinction of solid fibre, chosen so that a yarn's
    middle has `optical_depth` across its width (2 r). It depends on the
    yarn, not on the voxel size: the density grid is the fibre volume
    fraction, so the same garment at any resolution (and any level of
    detail, whose voxels are means) holds the same fibre and renders alike."""
    return optical_depth / (2.0 * yarn_radius)


def add_volume(context, name, vdb_path, density, viewport_level, albedo):
    volume = bpy.data.volumes.new(name)
    volume.filepath = vdb_path
    volume.render.space = "WORLD"  # step size and density in world units, whatever the object's scale
    volume.render.step_size = 0.0  # automatic: from the voxel size
    obj = bpy.data.objects.new(name, volume)
    context.collection.objects.link(obj)
    obj.data.materials.append(make_material(name, density, viewport_level, albedo))
    return obj


def _principled(nodes, attribute, density, albedo, suffix):
    p = nodes.new("ShaderNodeVolumePrincipled")
    p.inputs["Density"].default_value = density
    p.inputs["Density Attribute"].default_value = attribute
    p.inputs["Absorption Color"].default_value = (0, 0, 0, 1)  # extinction exactly Density x attribute
    if albedo:
        p.inputs["Color"].default_value = (1, 1, 1, 1)
        p.inputs["Color Attribute"].default_value = "albedo" + suffix
    else:
        p.inputs["Color"].default_value = (0.8, 0.28, 0.22, 1)
    return p


def make_material(name, density, viewport_level, albedo):
    """Cycles renders level 0 (`density`); Eevee and the viewport's material
    preview a coarse level (`density_lodL`) through their own output."""
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    nodes.clear()
    render_out = nodes.new("ShaderNodeOutputMaterial")
    render_out.target = "CYCLES"
    links.new(_principled(nodes, "density", density, albedo, "").outputs["Volume"], render_out.inputs["Volume"])
    if viewport_level > 0:
        suffix = f"_lod{viewport_level}"
        preview_out = nodes.new("ShaderNodeOutputMaterial")
        preview_out.target = "EEVEE"
        links.new(_principled(nodes, "density" + suffix, density, albedo, suffix).outputs["Volume"],
                  preview_out.inputs["Volume"])
    else:
        render_out.target = "ALL"
    return material
