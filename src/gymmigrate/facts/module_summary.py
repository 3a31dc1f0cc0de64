"""What the run knows of one module: the small picklable ``ModuleSummary`` that
``facts/summaries/`` makes of each file and ``facts/project.py`` joins, and the
conventions of the names it holds (a kind not yet resolved: ``new:``, ``ref:``, ``param:``, ``held:``,
``@`` for a def of the module itself, ``?.`` for a call whose owner is unknown).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

from gymmigrate.facts.creator_tables import Field
from gymmigrate.facts.done_causes import DoneCause
from gymmigrate.facts.init_attributes import ClassStores
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.reset_contract import ResetSites

# Kinds an unresolved ``x.fit(venv)`` still reports against every ``fit`` of the run.
GUARD_KINDS = frozenset({EnvKind.SB3_VEC, EnvKind.GYM_VEC, EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL})
UNRESOLVED = "?."
NEW = "new:"
REF = "ref:"
OWN = "@"  # a def of the calling module itself
PARAM = "param:"
# In a ``new:`` union, a kind the calling module settles itself (``new:envs.Reacher|=GYM_ENV``:
# a name bound to ``Reacher()`` in one branch and ``gym.make(...)`` in another).
KNOWN = "="
# ``held:Trainer.__init__:test_env``: ``self.test_env`` of a plain class of the calling module,
# stored only from that ``__init__`` parameter: what every construction of the run passes there.
HELD = "held:"
# ``table:agents.factory.AGENTS``: a lookup in a closed table of creators of another module of
# the run. As a call's target, the call reaches each class or def the table holds; as what
# calling an argument gives (``CallSummary.creators``), what calling through the table gives.
TABLE = "table:"
# In ``ModuleSummary.fixtures``: another fixture a fixture takes and returns as it is
# (``fixture:env``), and a value that is a ``make(...)`` result, maybe in Gym wrappers.
FIXTURE = "fixture:"
MADE_VALUE = "made"
# Beyond this many parameters passed on from call to call the join stops following.
MAX_CHAIN = 50
Kind = EnvKind | str  # a kind, or ``new:<class>[|<class>...]`` / ``param:<def>:<name>`` / ``held:...`` until the join resolves it


class InitHeld(NamedTuple):
    """What a class of the run holds in an attribute from its ``__init__`` (``ProjectFacts.init_held``)."""

    param: str  # the ``__init__`` parameter
    position: int  # its position in a call (no ``self``)
    handed_on: bool  # the class is a Gym env wrapper written by hand around the attribute


# An argument made right there by ``gym.make`` and handed only to calls of the run
# (``facts/mode_handovers.py``): (its slot: position or keyword, the make's line and column,
# its id when a literal, how many calls of the run the module hands that env to, its name
# when bound at module level, whether the call's result is only the owner of method calls).
HandedMake = tuple[str, int, int, str | None, int, str, bool]


@dataclass(frozen=True)
class CallSummary:
    target: str  # "agent.Agent.fit", ".agent.train", "?.fit" (owner unknown)
    args: tuple[Kind, ...]  # by position, up to the first starred argument
    keywords: tuple[tuple[str, Kind], ...]
    open_ended: bool  # ``*args`` / ``**kwargs`` at the call: later parameters are unknown
    # Arguments that are env ids (``"PongNoFrameskip-v4"``, or a module constant bound once to
    # one): (position as a string, or the keyword, the id). What ids a factory is given.
    ids: tuple[tuple[str, str], ...] = ()
    line: int = 0  # where the call is (a message naming the module that passes an env)
    # Arguments that are lists of thunks (``[make_env(i) for i in range(n)]``): (position as a
    # string, or the keyword, what calling every item returns: ``thunk_list_kind``).
    # ``ref:<qualified>`` for one whose items are all calls of one imported def of the run.
    thunks: tuple[tuple[str, Kind], ...] = ()
    made: tuple[HandedMake, ...] = ()
    # Arguments that are names: (position as a string, or the keyword, ``Flow.source_of``):
    # which variable of the caller each hands on (two defs fed the same one hold the same values).
    sources: tuple[tuple[str, str], ...] = ()
    # Arguments that are lists of envs the module shows every item of (``[OwnVecEnv(fns)
    # for _ in range(n)]``, a name or ``self.x`` bound to one): (position as a string, or the
    # keyword, the one kind every item has). What ``envs[i]`` holds in the def given it.
    items: tuple[tuple[str, Kind], ...] = ()
    # Arguments that are classes or other creators (``env_class=CartEnv``, ``ENVS[name]``, a
    # name bound once to either, a parameter of the calling def passed on): (position as a
    # string, or the keyword, what calling it gives: a kind, ``ref:<qualified>`` for a name of
    # the run, ``table:<qualified>`` for a lookup in a table of the run, ``param:...``).
    creators: tuple[tuple[str, Kind], ...] = ()
    # Arguments that are lists of thunks whose every item returns an env of one Gym-only
    # library stack (GM107; ``thunk_list_stack``): (position as a string, or the keyword,
    # that stack). What the env functions handed to a vec env class make.
    thunk_stacks: tuple[tuple[str, str], ...] = ()
    # Arguments that are instances of a class of the run (``Holder(name)``, or a name every
    # binding reaching the call builds one): (position as a string, or the keyword, ``@Name``
    # for a class of the calling module, else its qualified name). What ``holder.env`` is in
    # the def given it (``ProjectFacts.held_made``).
    holders: tuple[tuple[str, str], ...] = ()
    # ``super().__init__(...)`` (any ``super().m(...)``) in a subclass: it runs the base's
    # method on an instance of the subclass, and builds no instance of the base.
    up: bool = False


@dataclass(frozen=True)
class Signature:
    params: tuple[str, ...]  # positional-or-keyword, ``self`` included for methods
    defaults: frozenset[str]  # parameters with a default value
    is_method: bool


@dataclass(frozen=True)
class ModuleSummary:
    path: str  # os.path.realpath of the file
    defs: dict[str, Signature]  # "train", "Agent.fit", "Agent.__init__"
    env_classes: frozenset[str]  # top-level classes whose instances are Gym envs
    render_mode_classes: frozenset[str]  # ...whose constructor takes render_mode once migrated
    calls: tuple[CallSummary, ...]
    # ``x.seed(...)`` on a receiver this module cannot trace: an env class it imports from
    # the run must keep its seed() (removing it would make that call an AttributeError).
    untraced_seed_call: bool = False
    # ``x.render(mode)`` likewise: an env class it imports must keep render(mode).
    untraced_render_call: bool = False
    # ``x.configure(...)`` on anything but ``self`` / ``super()``: a caller of the gym < 0.9
    # hook renamed from ``_configure`` that the class itself does not decide (GM405).
    calls_configure: bool = False
    # ``x.seed(...)`` / ``x._seed(...)`` on anything but a library module or a space
    # (``summaries.untraced.calls_seed``): a call that may reach an env class's seed().
    calls_seed: bool = False
    # one of those calls passes no seed (``summaries.untraced.calls_seed_without_a_value``)
    calls_seed_without_a_value: bool = False
    # ``x.reset(return_info=False)`` (or any mode but ``True`` not handed on by a reset):
    # a caller of a gym 0.22-0.25 reset that may expect the bare observation (GM502).
    passes_return_info: bool = False
    # qualified names of the run that made the receivers of ``x.render(mode)`` calls no make
    # of the module created (``pkg.make_board``): a def among them leaves the mode in place
    render_makers: frozenset[str] = frozenset()
    # ``env.seed(s)`` on what only the join can classify (``A()`` in one branch, ``B()`` in
    # another, names of the run): per call, the makers of its receiver joined by ``|``
    # (``CallSummarizer.reaching_makers``). GM203 rewrites the call where they all give Gym
    # envs, leaving no caller; otherwise it stays, an untraced seed() caller.
    seed_makers: frozenset[str] = frozenset()
    imported: tuple[str, ...] = ()  # qualified names its imports bind
    # ``# gymmigrate: skip-file``: the module stays as it is, so the run must not assume it migrated.
    skips_file: bool = False
    # Top-level name -> the kind of what calling it gives (a class: its instances; a def or
    # an alias of ``gym.make``: what it returns), or ``ref:<qualified>`` for a name bound to
    # another module's (a re-export, ``from .utils import make``, a subclass of a class of
    # the run): the join follows it. Every top-level def, class and import is listed, so the
    # run knows which names it defines itself.
    exports: dict[str, Kind] = field(default_factory=dict)
    star_imports: tuple[str, ...] = ()  # ``from .utils import *``: modules whose names it re-exports
    # Names its top-level classes derive that the module never binds itself: with star
    # imports, they may come from one (``ProjectFacts.star_bindings``).
    star_bases: frozenset[str] = frozenset()
    # Its ``__all__`` (what a star import of it binds), None without one; () where the
    # module builds it in a way its text does not show (a star import of it binds nothing sure).
    declared_all: tuple[str, ...] | None = None
    # Top-level name -> the library callable it is bound to (``make = gym.make``,
    # ``from gym import make``): a creation site of the run that takes ``make``'s keywords.
    aliases: dict[str, str] = field(default_factory=dict)
    # (top-level name, field) of each closed table of creators (``facts/creator_tables.py``;
    # field "" for its values themselves) -> what calling each value (or each record's
    # field) gives, as ``exports``: the modules that call through ``T[k](...)`` read it.
    tables: dict[tuple[str, Field], tuple[Kind, ...]] = field(default_factory=dict)
    # ...and whether each callable there returns a ``make(...)`` result: ``@`` (shown here),
    # ``ref:<qualified>`` (a call of a name of the run: made when the run says so), "" (not shown)
    made_tables: dict[tuple[str, Field], tuple[str, ...]] = field(default_factory=dict)
    # Qualified names of imported names this module writes into (``T[k] = v``): no table.
    altered: frozenset[str] = frozenset()
    # -- method contracts across modules (rules/custom_env/hooks.py) --
    # Each top-level class with a base imported from elsewhere: (class, qualified base
    # names as the imports spell them, the methods the class defines).
    subclasses: tuple[tuple[str, tuple[str, ...], tuple[str, ...]], ...] = ()
    # Top-level class -> the names its methods call as ``self.<name>(...)``: a helper a
    # subclass elsewhere defines may be called by its base here, so its return is shared.
    self_calls: dict[str, frozenset[str]] = field(default_factory=dict)
    # Top-level class -> the names its methods call on a base (``super().m(...)``,
    # ``Base.m(self, ...)``), and -> its bases of the run in the order it names them (``@Name``
    # for one of this module), and -> the gym <= 0.9 hooks it renames (``_reset`` ->
    # ``reset``) on this module's knowledge: the join finds the callers in other modules of a
    # method the run removes or renames (``facts/project_hooks.py``).
    super_calls: dict[str, frozenset[str]] = field(default_factory=dict)
    # Top-level class -> the methods it calls as ``Cls.m(self, ...)``: past its MRO's order.
    named_class_calls: dict[str, frozenset[str]] = field(default_factory=dict)
    run_bases: dict[str, tuple[str, ...]] = field(default_factory=dict)
    renamed_hooks: dict[str, frozenset[str]] = field(default_factory=dict)
    # The methods the module calls on another receiver than ``self`` or ``super()``
    # (``env.postprocess(...)``): a helper of a class elsewhere that step returns keeps
    # its own return when this module may call it directly (``common.delegates``).
    instance_calls: frozenset[str] = frozenset()
    # ``make(env.spec)`` or ``env.spec.make()``: Gymnasium rebuilds the wrappers of the spec
    # from their recorded constructor arguments (GM617).
    recreates_from_spec: bool = False
    # Top-level Gym wrapper classes (``Wrapper`` subclasses, through local bases): an
    # instance made elsewhere is a wrapper, so what it does not define was forwarded.
    wrapper_classes: frozenset[str] = frozenset()
    # Top-level plain classes shaped as duck wrappers (``receiver_classes.duck_wrapper_slot``)
    # that this module alone cannot prove -> the ``__init__`` parameter they hold: the join
    # makes their instances Gym envs where every construction of the run passes one there.
    duck_wrappers: dict[str, str] = field(default_factory=dict)
    # Top-level Gym wrapper classes (bases of this module or Gym's) -> what they define for
    # ``self``: a subclass elsewhere that reads another name read a forwarded attribute.
    wrapper_defined: dict[str, frozenset[str]] = field(default_factory=dict)
    # Top-level defs that return their first argument, maybe in Gym wrappers
    # (``Receivers.wraps_argument``): what they give has the kind of what they take.
    # def name -> the name of that parameter, which a call may pass by keyword.
    wrapping_helpers: dict[str, str] = field(default_factory=dict)
    # Top-level PettingZoo wrapper classes and aliases of PettingZoo's wrapper bases
    # (``facts/pz_wrappers.py``): name -> ("aec" | "parallel" | "ref:<qualified>", methods).
    pz_wrappers: dict[str, tuple[str, tuple[str, ...]]] = field(default_factory=dict)
    # -- spaces that are not Spaces (rules/env_ids/registry.py, GM807) --
    # Top-level classes that certainly are not ``gymnasium.spaces.Space``: no base, or only
    # ``list``/``tuple``/``dict``/``object``, with what they derive from ("list").
    plain_classes: dict[str, str] = field(default_factory=dict)
    # Top-level class -> ((space attribute, callee as the module spells it), ...) for each
    # ``self.action_space = C(...)`` / ``self.observation_space = C(...)`` in its methods;
    # ``@C`` for a class of the module itself.
    space_calls: dict[str, tuple[tuple[str, str], ...]] = field(default_factory=dict)
    # -- spaces whose ``contains()`` the run asks (rules/spaces/box_contains.py, GM910) --
    # (the name the receiver is read by, line) per ``x.contains(value)``: ``space`` for
    # ``space.contains(o)``, ``observation_space`` for ``env.observation_space.contains(o)``.
    contains_calls: tuple[tuple[str, int], ...] = ()
    # -- the mujoco-py API read outside a MujocoEnv subclass (rules/custom_env/observations.py, GM508) --
    # Lines reading what only a mujoco-py MujocoEnv has (``x.model.data``, ``x.model.geom_names``,
    # ``x.model.body_name2id(...)``, ``x.data._wrapped``) on another object than ``self`` or an
    # MjSim, and the old base's ``_render`` / ``_get_viewer`` called on that same object.
    mujoco_py_uses: tuple[int, ...] = ()
    # -- spaces an env leaves unset (facts/space_setters.py, GM511) --
    # Top-level class -> (the spaces its own code leaves unset once constructed, its bases
    # of the run, ``@Name`` for one of this module); a class that sets both, or whose code
    # cannot show it, is not listed.
    unset_spaces: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = field(default_factory=dict)
    # Of those, the classes whose construction runs their base's ``__init__`` (none of their
    # own, or one that calls it): a space their base sets would be theirs too.
    base_built: frozenset[str] = frozenset()
    # Top-level def -> the classes it may construct (``@Name``, or the qualified name of a
    # name of the run), through the defs of the module it calls: what a registered def makes.
    def_builds: dict[str, tuple[str, ...]] = field(default_factory=dict)
    # The literal entry points of its ``register(...)`` calls that leave the env checker on.
    checked_entries: tuple[str, ...] = ()
    # -- envs whose reset steps their own wrappers (facts/wrapper_steps.py, GM808) --
    # Top-level class -> (attribute, setter) pairs: its reset steps ``self.<attribute>``,
    # which the class's method ``setter`` stores from a parameter ("": stored from outside).
    reset_steps: dict[str, tuple[tuple[str, str], ...]] = field(default_factory=dict)
    # What the methods of the module's wrapper classes (or subclasses of a class of another
    # module) hand ``self`` to: ``m`` for ``x.m(self)``, ``=a`` for ``x.a = self``.
    self_handoffs: frozenset[str] = frozenset()
    # Top-level names bound once to a list of the registry's EnvSpecs
    # (``[spec for spec in gym.envs.registry.values() if ...]``): ``spec.make(...)`` on one
    # of them makes an env (``facts/env_specs.py``).
    spec_lists: frozenset[str] = frozenset()
    # Top-level defs every return of which is a ``make(...)`` result (maybe in Gym wrappers):
    # what they return is a wrapper stack, so attribute reads on it go through forwarding.
    made_factories: frozenset[str] = frozenset()
    classes: frozenset[str] = frozenset()  # top-level class names
    # Top-level classes whose own ``__init__`` hands its arguments up with
    # ``super().__init__(...)`` to a first base of another module of the run: that call is
    # among ``calls`` (target ``<base>.__init__``), so the base sees what they pass.
    passes_init_up: frozenset[str] = frozenset()
    # Top-level defs whose every return is an env of a Gym-only library stack (GM107), maybe
    # in the module's own wrappers: def -> the stack (``nes_py``). Its callers' resets and
    # steps are that stack's port (``Receivers.gym_only_stack``).
    gym_only_makers: dict[str, str] = field(default_factory=dict)
    # -- what a flag passed to a def is for (facts/bootstrap.py, GM302) --
    # "Agent.train_model" -> (flag parameter, next-state parameter) pairs: the def masks
    # bootstrapping from the next state with the flag (a target or a stored transition).
    bootstrap_masks: dict[str, frozenset[tuple[str, str]]] = field(default_factory=dict)
    # A module with no Gym code (an agent's ``learn``): only its ``bootstrap_masks`` count,
    # it takes no other part in the join (``summaries.summarize_masks``).
    masks_only: bool = False
    # Top-level record classes (``Transition = namedtuple(...)``, a ``NamedTuple`` or a
    # ``@dataclass``): a module that builds one imported from here stores its fields as a
    # tuple would (GM302 reads a ``done`` given to it as stored data).
    record_classes: frozenset[str] = frozenset()
    # Top-level classes deriving only ``object`` or ``abc.ABC`` (``plain_roots``): a project's
    # own interface, no env of any library, whose seed() only the project calls (GM203).
    plain_roots: frozenset[str] = frozenset()
    # -- done values across modules (facts/limits.py) --
    # Class (with an imported base) -> its methods that return a value -> why that value is
    # True (a step limit, the task's end...), traced in the class; and for those returning
    # tuples of one length, why each of their values is True.
    done_methods: dict[str, dict[str, DoneCause]] = field(default_factory=dict)
    done_items: dict[str, dict[str, tuple[DoneCause, ...]]] = field(default_factory=dict)
    # -- step hooks across modules (facts/step_hooks.py) --
    # Class -> the hooks its step returns (``return self.post_step(...)``) that this module
    # can follow; class -> its methods whose returns can take five values with a base's hook.
    step_hooks: dict[str, frozenset[str]] = field(default_factory=dict)
    plain_overrides: dict[str, frozenset[str]] = field(default_factory=dict)
    # -- a class's own step as subclasses and its own methods use it (facts/own_steps.py) --
    # Class -> how many overrides in this module build on its step, which returns the
    # observation alone (every override returns its own step values); class -> whether its
    # step, which returns its own step values, builds on its base's; the classes whose
    # step, and every step of this module's classes below them, gives five values once migrated.
    helper_candidates: dict[str, int] = field(default_factory=dict)
    # candidate -> the classes below it here whose step is its own (none, or one that only
    # hands it on), each with whether it needs a class below it elsewhere
    helper_hand_ons: dict[str, tuple[tuple[str, bool], ...]] = field(default_factory=dict)
    own_step_shapes: dict[str, bool] = field(default_factory=dict)
    five_step_trees: frozenset[str] = frozenset()
    # Stores of ``np_random`` (``facts/rng_handovers.py``): (line, to another object than
    # ``self``, the value is a Generator, the class built into that object just before). A class elsewhere that only reads its np_random
    # follows the run's handovers when every store is a Generator (GM505).
    rng_stores: tuple[tuple[int, bool, bool, str], ...] = ()
    # Top-level classes with a base: (their own body counts steps, bases of this module,
    # other bases' qualified names) (``facts/step_counts.py``): a subclass in another module
    # whose bases count nothing cannot end episodes on a limit of its own (GM504).
    step_counting: dict[str, tuple[bool, tuple[str, ...], tuple[str, ...]]] = field(default_factory=dict)
    # Top-level classes deriving a library class with an env API of its own (``class
    # Adapter(dm_env.Environment)``, directly or through a class of this module): the join
    # adds their subclasses in other modules (``ProjectFacts.own_api_classes``).
    own_api_classes: frozenset[str] = frozenset()
    # Top-level classes of two APIs whose step and reset take Gymnasium's shapes only under
    # ``if self.<flag>:`` (``own_api.gymnasium_flag``): class name -> flag. A subclass in
    # another module that sets the flag True takes those shapes (GM504).
    own_api_flags: dict[str, str] = field(default_factory=dict)
    # GM402 across modules (``facts/render_handovers.py``): (def, parameter) rendered bare
    # and handed nowhere; calls passing an env built right there by an imported class:
    # (call line, slot, class, construction line, column).
    bare_render_params: frozenset[tuple[str, str]] = frozenset()
    handed_constructions: tuple[tuple[int, str, str, int, int], ...] = ()
    # GM401 across modules (``facts/mode_handovers.py``): (def or ``Class.__init__``,
    # parameter, the one literal frame mode its env is rendered in, "" for none) for each
    # parameter whose env goes nowhere else.
    param_renders: tuple[tuple[str, str, str], ...] = ()
    # -- contracts the run keeps (facts/class_shapes.py keeps_legacy_step) --
    # Top-level env classes whose step keeps the four-field contract (a batch the rules do
    # not migrate), and Gym wrappers of the project's own protocol (a step returning its own
    # record): the callers of their instances keep that contract, reset included.
    legacy_steps: frozenset[str] = frozenset()
    # Top-level classes whose reset (their own, or a base's of this module) the run keeps
    # as it was (``Receivers.reset_kept``): it takes no seed/options after the run.
    kept_resets: frozenset[str] = frozenset()
    # Top-level Gym wrapper classes every construction here puts around, and factories that
    # return on every path, an instance of one imported name (the import as written): they
    # keep that name's contract when the run keeps it (``project_contracts.legacy_steps``).
    # Imported names put around it come first: ``a.Outer>b.Kept`` for ``Outer(Kept(env))``.
    legacy_if: dict[str, str] = field(default_factory=dict)
    # Top-level Gym wrapper classes whose step and reset hand on the wrapped env's results
    # unchanged (``Receivers.forwards_inner_contract``): put around an instance the run keeps
    # on the legacy API in any module, they keep it too.
    forwarding_wrappers: frozenset[str] = frozenset()
    # Top-level classes whose render() (their own, or a base's of this module) neither calls
    # a render() nor asks workers to render: a project's stub (``logger.warn(...)``), whose
    # callers need no render_mode anywhere (rules/rendering/).
    silent_renders: frozenset[str] = frozenset()
    # Top-level classes that declare metadata render modes (-> them), or have exactly one
    # base to inherit them from (-> None) (``frame_modes.frame_classes``): which envs give
    # no frames for a legacy Monitor to record.
    frame_classes: dict[str, tuple[str, ...] | None] = field(default_factory=dict)
    # classes whose render() forwards bare to the env they hold -> line of that forward
    render_forwards: dict[str, int] = field(default_factory=dict)
    # Top-level classes with an imported base that render themselves with a mode
    # (``self.render(mode="rgb_array")``) and define no render(): class -> (line, call). That
    # call reaches the base's render() in another module, which must keep its ``mode``.
    mode_renders: dict[str, tuple[int, str]] = field(default_factory=dict)
    # Top-level classes whose render(mode) cannot keep ``mode`` as an optional parameter
    # (``mode_can_stay_optional``): kept whole for such callers, they take no render_mode.
    fixed_mode_renders: frozenset[str] = frozenset()
    # Top-level classes whose own render() has a ``mode`` parameter with a default: a bare
    # render() (Gymnasium's wrappers call it with no arguments) still reaches that default.
    default_mode_renders: frozenset[str] = frozenset()
    # The module registers envs whose entry points are no literal (read from a data file):
    # the ids its importers make may name any env class of the run.
    opaque_registrations: bool = False
    # Top-level Gym wrapper classes whose reset/step call ``self.env.render(...)``: an env
    # another module wraps in one was drawn as it ran (rules/rendering/planning.py).
    rendering_wrappers: frozenset[str] = frozenset()
    # Top-level classes with a base of the run (``@Name`` for one of this module): (class,
    # bases, whether its ``__init__`` hands ``render_mode`` on once a base takes it). The
    # join threads ``render_mode`` down every chain of subclasses (custom_env/render.py).
    render_mode_heirs: tuple[tuple[str, tuple[str, ...], bool], ...] = ()
    # Top-level env classes whose render(self, mode="human") only hands its mode on to
    # objects that are no Gym env, and that no render call of this module passes a mode to
    # (``render_modes.own_object_render``): (class, what made each of those objects: "" where
    # this module shows it is its own, else the qualified class the join checks).
    own_renders: tuple[tuple[str, tuple[str, ...]], ...] = ()
    # Top-level env classes whose render(self) draws the same whatever render mode they are
    # made with (``render_modes.modeless_render``): a bare render() of one asks for none.
    modeless_renders: frozenset[str] = frozenset()
    # Top-level classes whose own render(self, *args) names no mode: the run leaves it, and a
    # mode passed to one of its instances still reaches it (``classes.varargs_renders``).
    varargs_renders: frozenset[str] = frozenset()
    # Top-level env classes whose drawing is their render() alone: step() and reset() call no
    # render() (``render_modes.draws_only_in_render``). Made in human mode, they still draw
    # only when render() is called.
    render_only_classes: frozenset[str] = frozenset()
    own_flag_steps: frozenset[str] = frozenset()  # classes whose step() draws only on flags of their own
    # -- a reset contract of the run (facts/reset_contract.py, GM207) --
    # The extra reset keywords its env classes take, its reset calls pass, and the sites
    # the rewrite cannot carry.
    reset_sites: ResetSites = field(default_factory=ResetSites)
    # ``register(id, entry_point="pkg.mod:Class")``: (the id if a literal, the entry point).
    registrations: tuple[tuple[str | None, str], ...] = ()
    # The module calls what loads an earlier run's policy, weights or normaliser
    # (``summaries.defs.loads_model_for_the_run``): a new env version is a question for the run.
    loads_saved_state: bool = False
    # The ids of every Gym ``register(...)`` call, whatever its entry point (None: no literal).
    registered_ids: tuple[str | None, ...] = ()
    # Env-id-shaped strings of the module besides its register() ids (``pkg:`` dropped), and
    # whether a Gym make() of it passes an id that is no literal (``summaries.defs.named_ids``):
    # a registered id no module names is made by nothing of the run (GM511).
    named_ids: frozenset[str] = frozenset()
    opaque_make: bool = False
    # Top-level classes this module cannot classify (their bases are another module's) whose
    # constructor takes render_mode once migrated, where the run shows them env classes.
    render_mode_if_env: frozenset[str] = frozenset()
    # Top-level plain classes (no env, no wrapper) -> {attribute: ``__init__`` parameter} for
    # each attribute only ever stored from that parameter (``self.gym_env = gym_env``): an
    # instance's attribute is what every construction of the run passes there.
    held_params: dict[str, dict[str, str]] = field(default_factory=dict)
    # The same for top-level classes of any kind (a proxy deriving a plain class of another
    # module, a Gym env storing the env it wraps), with whether the class is a Gym env wrapper
    # written by hand around the attribute (its step and reset are the held object's,
    # ``class_shapes.handed_on_attribute``): what a subclass elsewhere that hands its own
    # parameter up to that ``__init__`` holds there (``ProjectFacts.init_held``).
    init_held: dict[str, dict[str, tuple[str, bool]]] = field(default_factory=dict)
    # Top-level class -> {property: attribute} for each ``@property`` that only returns
    # ``self.<attribute>`` (``class_shapes.property_aliases_of``): a subclass in another module
    # reading the property reads that attribute (``ProjectFacts.property_aliases``), and holds
    # there what it hands up to ``init_held`` (``SelfAttributes.handed_up``).
    property_aliases: dict[str, dict[str, str]] = field(default_factory=dict)
    # Top-level classes -> {attribute: kind} for each attribute the class resets or steps
    # (``self.env.step(a)``), or holds an env of a known API in, and stores only from
    # constructions this module settles (``self.env = ParallelPettingZooEnv(...)``,
    # ``self.env = gym.make(env_id)``): a subclass in another module that never stores it
    # holds the same object (``ProjectFacts.driven_kinds``).
    driven_kinds: dict[str, dict[str, EnvKind]] = field(default_factory=dict)
    # Top-level classes with an imported base of the run -> the attributes they (or their
    # bases of this module) store on ``self``: another attribute they hold is a base's, so
    # what a base of any depth drives there is theirs too (``inherit_driven_kinds``).
    stored_attributes: dict[str, frozenset[str]] = field(default_factory=dict)
    # Imported names of the run read as a value, not called (``partial(wrappers.make_env, i)``,
    # ``fn=make_env``): they may be called with arguments no summary sees.
    handed_on: frozenset[str] = frozenset()
    # Top-level defs and classes that use what only an Atari env has (``facts/atari_signs.py``):
    # a module that hands its env to one makes Atari envs (GM106 adds ``import ale_py``).
    atari_users: frozenset[str] = frozenset()
    # Defs and methods (``Worker.__init__``) -> their parameters that carry an env id to a Gym
    # id call of this module (``facts/id_params.py``): a literal another module passes there
    # is an id (GM803-GM805 rename it at that call).
    id_params: dict[str, frozenset[str]] = field(default_factory=dict)
    # ``self.check(environment="LunarLander-v2")`` calling a method the class inherits from
    # a base of another module: seen by that join only (``CallSummarizer.inherited_id_calls``).
    inherited_id_calls: tuple[CallSummary, ...] = ()
    # Defs and methods -> their parameters whose value goes on (``id_params.escaping_parameters``):
    # a retired id passed to any other parameter of a def of the run reaches no make.
    escaping_params: dict[str, frozenset[str]] = field(default_factory=dict)
    # Top-level defs that return a thunk on every path (``make_env`` returning a nested def
    # around ``gym.make``) -> what calling that thunk returns (``factory_thunk_kind``).
    thunk_factories: dict[str, EnvKind] = field(default_factory=dict)
    # Top-level defs whose thunks, on every path, return a call of a name another module of
    # the run defines (``def creator(_): return Orchard(n)`` with ``Orchard`` imported) ->
    # those names: the join gives the def the one kind their calls give there
    # (``ProjectFacts.thunk_factories``), which this module alone cannot know.
    thunk_factory_refs: dict[str, frozenset[str]] = field(default_factory=dict)
    # Top-level defs that return, on every path, a tuple of one size holding a thunk of their
    # own at one index (``return create_env, env_name``) -> (index, size, what calling that
    # thunk returns): ``create, _ = make_creator(...)`` then ``create()`` in another module.
    thunk_items: dict[str, tuple[int, int, EnvKind]] = field(default_factory=dict)
    # Top-level defs whose thunk (the whole return: None; else (index, size) of the tuple
    # item, as ``thunk_items``) returns ``make(...)`` results on every path, maybe in Gym
    # wrappers: a wrapper stack, whose own attributes need ``get_wrapper_attr`` (GM604).
    made_thunks: dict[str, tuple[int, int] | None] = field(default_factory=dict)
    # -- what a class's instances certainly hold (facts/init_attributes.py, GM604, GM507) --
    # Top-level class -> its bases, the names its body binds, and what each of its methods
    # certainly stores on ``self``, calls on ``self`` and hands up to a base ``__init__``:
    # the join follows the bases across modules (``ProjectFacts.init_attributes``).
    class_stores: dict[str, ClassStores] = field(default_factory=dict)
    # Top-level classes deriving only ``object``, no Gym env or wrapper -> the attributes every
    # store of which is what ``gym.make`` returned, bare (``facts/made_holders.py``): on an
    # instance, ``holder.env.env`` is a chain through make's own layers.
    made_holders: dict[str, frozenset[str]] = field(default_factory=dict)
    # -- pytest fixtures (facts/summaries/fixtures.py) --
    # For a ``conftest.py``: fixture (pytest's name for it) -> (its def, what each value it
    # returns or yields is: ``made``, ``ref:<qualified>``, ``@Name``, ``fixture:<name>``, "").
    # The tests below it take these by parameter name (``ProjectView.fixture_kind``).
    fixtures: dict[str, tuple[str, tuple[str, ...]]] = field(default_factory=dict)


def is_ref(kind: object) -> bool:
    """A re-export (``ref:<module>.<name>``), not a resolved kind: ``EnvKind`` is a ``str``
    enum, so ``isinstance(kind, str)`` alone does not tell them apart."""
    return isinstance(kind, str) and not isinstance(kind, EnvKind) and kind.startswith(REF)
