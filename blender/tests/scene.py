"""What the add-on's tests build in Blender: an object with a generated
256x256 colour grid on its material's base colour (an Image Texture node
into the Principled BSDF, as an artist's material)."""
import bpy


def textured(obj, image_name, material_name):
    """Gives obj a material material_name whose base colour is a new 256x256
    COLOR_GRID image image_name; returns the image."""
    image = bpy.data.images.new(image_name, 256, 256)
    image.generated_type = "COLOR_GRID"
    mat = bpy.data.materials.new(material_name)
    mat.use_nodes = True
    tex = mat.node_tree.nodes.new("ShaderNodeTexImage")
    tex.image = image
    mat.node_tree.links.new(tex.outputs["Color"], mat.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
    obj.data.materials.append(mat)
    return image
