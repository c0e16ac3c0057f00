"""The add-on's panels drawn into a recorder instead of Blender's layout, so that
every text they show can be measured against the room the sidebar gives it
(tests/test_addon_workflows.py; in a window, scenario panel_fit, also against
the real sidebar's width).

The recorder keeps Blender's layout rules that decide a text's room: a column
gives each item its whole width, a row shares it between its items, a box
takes its border; the costs of an icon, a checkbox, a button and a drop-down
are the add-on's own measurements (panels.py). Each text is measured with blf
in the UI font at the UI scale, as Blender draws it."""
import bpy


class _Item:
    def __init__(self, kind, text, icon=False):
        self.kind, self.text, self.icon = kind, text, icon


class Layout:
    """Records what a draw function puts in a layout."""

    def __init__(self, kind="column", inset=0.0):
        self.kind = kind
        self.inset = inset
        self.items = []
        self.enabled = self.active = True
        self.alert = False
        self.scale_x = self.scale_y = 1.0
        self.use_property_split = self.use_property_decorate = False
        self.operator_context = "INVOKE_DEFAULT"

    # containers
    def _child(self, kind, inset=0.0):
        child = Layout(kind, inset)
        self.items.append(child)
        return child

    def column(self, align=False, heading=""):
        return self._child("column")

    def row(self, align=False, heading=""):
        return self._child("row")

    def box(self):
        return self._child("column", inset=panels().BOX_MARGIN)

    def split(self, factor=0.0, align=False):
        return self._child("row")

    def grid_flow(self, columns=0, **kw):
        return self._child("row")

    def separator(self, factor=1.0):
        pass

    # widgets
    def label(self, text="", icon="NONE", **kw):
        self.items.append(_Item("label", text, icon != "NONE"))

    def operator(self, idname, text=None, icon="NONE", **kw):
        if text is None:
            group, name = idname.split(".")
            text = getattr(getattr(bpy.ops, group), name).get_rna_type().name
        self.items.append(_Item("button", text, icon != "NONE"))
        return _Props()

    def prop(self, owner, name, text=None, icon="NONE", toggle=False, emboss=True, **kw):
        rna = owner.bl_rna.properties[name]
        label = rna.name if text is None else text
        value = getattr(owner, name)
        if rna.type == "ENUM":
            shown = next((i.name for i in rna.enum_items if i.identifier == value), str(value))
            self.items.append(_Item("dropdown", shown if not label else "%s: %s" % (label, shown), icon != "NONE"))
        elif rna.type == "BOOLEAN":
            kind = "button" if toggle or not emboss else "checkbox"
            self.items.append(_Item(kind, label, icon != "NONE"))
        elif rna.type == "STRING":
            self.items.append(_Item("field", label))
        else:
            self.items.append(_Item("field", label))

    def prop_search(self, owner, name, search_owner, search_name, text=None, **kw):
        self.items.append(_Item("field", text or ""))

    def prop_enum(self, owner, name, value, **kw):
        self.items.append(_Item("button", value))

    def context_pointer_set(self, *a):
        pass


class _Props:
    def __setattr__(self, name, value):
        pass


def panels():
    import importlib

    import addon_utils

    name = next(m.__name__ for m in addon_utils.modules() if m.__name__.split(".")[-1] == "developable_mesh")
    return importlib.import_module(name + ".panels")


class Context:
    """bpy.context with the region the panel is drawn in replaced."""

    def __init__(self, region_width, region=None):
        self._region = region if region is not None else type("Region", (), {"width": region_width})()

    @property
    def region(self):
        return self._region

    def __getattr__(self, name):
        return getattr(bpy.context, name)


def texts_that_do_not_fit(layout, context):
    """[(text, its width, the room it has)] of every text the layout would cut."""
    p = panels()
    room = p.Room(context)
    costs = {"label": 0, "checkbox": p.CHECKBOX, "button": p.BUTTON, "dropdown": p.DROPDOWN, "field": p.BUTTON}
    bad = []

    def walk(node, width):
        width -= node.inset * room.scale
        count = max(1, len(node.items)) if node.kind == "row" else 1
        each = width / count
        for item in node.items:
            if isinstance(item, Layout):
                walk(item, each)
                continue
            if not item.text:
                continue
            need = room.text_width(item.text) + (costs[item.kind] + (p.ICON if item.icon else 0)) * room.scale
            if need > each:
                bad.append((item.text, round(need / room.scale, 1), round(each / room.scale, 1)))

    walk(layout, room.width)
    return bad


def all_texts(layout):
    out = []
    for item in layout.items:
        out += all_texts(item) if isinstance(item, Layout) else ([item.text] if item.text else [])
    return out


def draw_panel(cls, context):
    """A panel's draw() into a recorder; returns the recorder."""
    layout = Layout()
    holder = type("Holder", (), {"layout": layout})()
    cls.draw(holder, context)
    return layout


def check_panels(context):
    """{panel: {"texts": [...], "cut": [...]}} for every panel of the add-on."""
    p = panels()
    out = {}
    for cls in p.classes:
        layout = draw_panel(cls, context)
        out[cls.__name__] = {"texts": all_texts(layout), "cut": texts_that_do_not_fit(layout, context)}
    return out
